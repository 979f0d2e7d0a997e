"""Old name of :mod:`delkit.bisimulation` (refinement, contraction, canonical forms), kept so that existing
imports keep working; new code imports :mod:`delkit.bisimulation`."""

from delkit.bisimulation import (  # noqa: F401
    bisimilar,
    bisimulation_classes,
    canonical_form,
    canonical_hash,
    contract,
    disjoint_union,
    quotient,
    refine,
)

__all__ = ["refine", "bisimulation_classes", "contract", "quotient", "bisimilar", "canonical_form", "canonical_hash",
           "disjoint_union"]
