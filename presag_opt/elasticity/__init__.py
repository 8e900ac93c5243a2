"""Elasticity of the contact wire along a span: uplift per unit upward point force.

Two independent methods:

- :func:`linear_elasticity` — from the tangent stiffness K at the form-found equilibrium (the
  Hessian of the CasADi potential): one sparse factorisation, one solve per contact-wire node of the
  span, then e(x) = N(x)ᵀ C N(x) + h t(1 − t)/T_CW with C the compliance block of those nodes, N the
  linear shape functions and the last term the string deflection inside the loaded element
  (:meth:`~presag_opt.static.discretisation.Discretisation.cw_element_compliance`), at any number of
  positions.
- :func:`nonlinear_elasticity` — equilibrium re-solved with the force F applied at each position,
  droppers free to go slack: e(x; F) = Δz(x)/F. Dropper unloading near the masts is the physical
  nonlinearity (Schick, Liu & Stichel 2025, Fig. 3).

Summary values follow the paper's notation: e_mid at mid-span, e_mast at the supports (mean of the
span's two ends), e_max, e_min, Δe = e_max − e_min, and the uniformity u = (e_max − e_min)/(e_max + e_min).

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016, section 4.1, eq. (5).

Modules
-------
curves
    :class:`ElasticityCurve` (one span, one force level, with its summary values) and
    :class:`ElasticityStudy` (several curves, and their JSON form).
methods
    The two methods: :func:`linear_elasticity`, :func:`nonlinear_elasticity` (``"newton"`` or
    ``"active-set"``).
study
    :func:`elasticity_study`: the curves of a span at several forces, in worker processes if asked,
    and :func:`uplift_warnings`.
"""

from presag_opt.elasticity.curves import ElasticityCurve, ElasticityStudy
from presag_opt.elasticity.methods import METHODS, linear_elasticity, nonlinear_elasticity, span_positions
from presag_opt.elasticity.study import DEFAULT_FORCES, elasticity_study, uplift_warnings

__all__ = [
    "DEFAULT_FORCES",
    "METHODS",
    "ElasticityCurve",
    "ElasticityStudy",
    "elasticity_study",
    "linear_elasticity",
    "nonlinear_elasticity",
    "span_positions",
    "uplift_warnings",
]
