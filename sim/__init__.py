"""Simulation: occupancy grids, communication-restricted exploration teams, search-and-rescue, experiments."""
