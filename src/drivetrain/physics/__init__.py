"""Formulas: one module per physical idea (inertia, loads, efficiency, stages, mechanisms, ...).

Plain functions with units and sources, and the frozen SI dataclasses they work on (``Stage``,
``Mechanism``, ``LinearLoad``, ...). Imports only the base layer (errors) and each other; the
axis file's models that build these objects live in ``drivetrain.axis``."""
