"""The other model-checking backends: the compact bit-set records the planner searches over
(:mod:`delkit.backends.compact`, its numpy refinement :mod:`delkit.backends.compact_np`) and the
BDD backend (:mod:`delkit.backends.symbolic` for S5, :mod:`delkit.backends.symbolic_belief` beyond,
:mod:`delkit.backends.bisimulation_symbolic`).
"""
