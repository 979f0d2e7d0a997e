"""The explicit models and what is done with them: accessibility relations, multi-pointed Kripke
models, event models, product update, composition of event models, bisimulation.

* :mod:`delkit.models.relation`, :mod:`delkit.models.kripke`, :mod:`delkit.models.events`
* :mod:`delkit.models.update`, :mod:`delkit.models.compose`, :mod:`delkit.models.bisimulation`
"""
