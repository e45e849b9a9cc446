"""The version of drivetrain (the one in pyproject.toml), for the answers and reports that name it.

Its own module, below every layer, so a module that stamps its answer with the version does not import
the package's public API (``drivetrain/__init__``), which imports the layers above it.
"""

__version__ = "0.1.0"
