"""The defaults of the jobs, in the designer's units: one place that the Python jobs and the command line
both read (the command line's help prints them).

Lengths of the design are in mm, shares in %, speeds in km/h, α_ae in N/(km/h)²; the numerics keep
their SI unit (an element length in m). This module imports nothing heavy, so that the command line
can read it at start-up.
"""

from __future__ import annotations

import os

from presag_opt.design.speed_range import STEADY_ARM_UPLIFT_LIMIT

WITHIN_PERCENT = 10.0
"""Allowed loss of the tolerance intervals (quasi-static and dynamic). [%]"""

UPLIFT_LIMIT_MM = STEADY_ARM_UPLIFT_LIMIT * 1e3
"""Steady-arm uplift limit: the case study's arms without uplift stop. [mm]"""

ELEMENT_LENGTH = 0.5
"""Longest element of the static model, every job: the paper's 0.5 m. [m]"""

ELASTICITY_STEP = 0.5
"""Point spacing of the elasticity curves of a band's Δe rule. [m]"""

LINE_ELASTICITY_STEP = 1.0
"""Point spacing of the elasticity curves of a line design (many spans: a coarser grid). [m]"""

WORKING_WIDTH_MM = 400.0
"""Half working width of the pantograph, the largest stagger a survey may carry. [mm]"""

DROPPER_STEP_MM = 5.0
"""Construction step of the dropper heights of a per-dropper robust design. [mm]"""

ROBUST_MODEL = "st_9.8_ideal"
"""The catenary of ``robust``, ``dynamic_robust`` and ``tolerance`` by default: the case study's ideal section."""

WORKERS = min(64, os.cpu_count() or 1)
"""Local worker processes by default: the CPU count (each job starts no more processes than it has work
for side by side). [-]"""

MONTE_CARLO_SAMPLES = 10_000
"""Realisations of the quasi-static Monte Carlo of installation errors (about a second). [-]"""

DYNAMIC_MONTE_CARLO_SAMPLES = 100
"""Realisations of the dynamic Monte Carlo of installation errors (tens of minutes on 2 cores). [-]"""

MAX_INSTALLATION_ERROR_MM = 100.0
"""Largest size of an installation error (a dropper's length, a mast's heights) the Monte Carlo accepts. [mm]"""

MAX_MONTE_CARLO_SAMPLES = 1_000_000
"""Most realisations of a Monte Carlo. [-]"""
