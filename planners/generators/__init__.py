"""Generators of planning instances with known solvability (see :mod:`planners.generators.frontier`)."""
