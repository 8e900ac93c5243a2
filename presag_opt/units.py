"""Unit conversions at the edges of the package (model files, command line, tables, plots).

Inside, every quantity is SI; a value in a user's unit is converted once, where it enters or leaves,
with the factor defined here.
"""

from __future__ import annotations

KMH = 1.0 / 3.6
"""One km/h in m/s. [m/s]"""
