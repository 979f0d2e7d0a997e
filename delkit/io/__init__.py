"""Model files: JSON (a documented schema) and DOT (:mod:`delkit.io.formats`), any model file the
core reads (:mod:`delkit.io.files`), and SMCDEL's input language (:mod:`delkit.io.smcdel`).
"""
