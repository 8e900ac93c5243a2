"""Global sensitivity of the toolkit's results to its assumed inputs (Morris screening, Sobol indices; SALib).

:mod:`~presag_opt.sensitivity.inputs` (which numbers, over which ranges), :mod:`~presag_opt.sensitivity.methods`
(the SALib designs and analyses), :mod:`~presag_opt.sensitivity.evaluation` (the samples evaluated in
workers, kept in a store, failures set apart), :mod:`~presag_opt.sensitivity.quasi_static` and
:mod:`~presag_opt.sensitivity.dynamic` (the outputs), :mod:`~presag_opt.sensitivity.analysis` (the job
behind ``presag sensitivity``). See docs/assumptions.md §7.
"""

from presag_opt.sensitivity.analysis import SensitivityResult, sensitivity_analysis
from presag_opt.sensitivity.inputs import SensitivityInput
from presag_opt.sensitivity.methods import MorrisEffect, OutputIndices, SobolIndex

__all__ = ["MorrisEffect", "OutputIndices", "SensitivityInput", "SensitivityResult", "SobolIndex",
           "sensitivity_analysis"]
