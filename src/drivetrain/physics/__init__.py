"""Formulas: one module per physical idea (inertia, loads, efficiency, stages, mechanisms, ...).

Imports only the base layer (errors, units, fields) and each other."""
