"""Planning on top of the delkit DEL engine: spec languages, epistemic and classical search, the e-PICO
hierarchy, action consistency (VERIFYAC/ENFORCEAC) and multi-robot task allocation."""
