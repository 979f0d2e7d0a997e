"""The logic: formulas (the AST, the text grammar and its printer), propositional reasoning with z3,
and model checking on Kripke models (one truth vector per subformula).

* :mod:`delkit.logic.formula`: the formula AST, ``parse`` and ``show``
* :mod:`delkit.logic.propositional`: propositional validity and satisfiability (z3)
* :mod:`delkit.logic.semantics`: vectorised model checking
"""
