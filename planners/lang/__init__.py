"""Readers for epistemic planning languages (mA*, E-PDDL) into grounded tasks."""
