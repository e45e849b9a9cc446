"""Machine projects: several axes on one or more DC buses, gantries with two motors, one report and one BOM.

``model`` reads the machine file, ``axes`` sizes each axis and gives its power at the bus,
``result`` sums the buses over the machine cycle (``size_machine``), ``aas`` exports the result
as an IDTA 02021 submodel. Layer 5: imports sizing and below.
"""
