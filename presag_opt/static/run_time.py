"""A rough wall time of form-finding, for the progress messages of long commands."""

from __future__ import annotations

from presag_opt.static import cache
from presag_opt.static.discretisation import StaticSettings, discretise
from presag_opt.system.catenary import Catenary

FORM_FIND_SECONDS = (0.3, 2.7, 12_000, 1.4)
"""Rough wall time of :func:`form_find` on one core of a 2-core 2026 virtual machine, as
a + b·(n/n_ref)^p with n the node count: measured 0.59 s at 2 413 nodes, 1.14 s at 4 813, 3.03 s at
12 013 (ST 9,8/9,8 ideal at 0.5, 0.25 and 0.1 m elements, each the first form-finding of a fresh
process without the cache; AMD EPYC, December 2026; the fit gives 0.58, 1.06 and 3.0 s). [s], [s], [-], [-]"""


def form_find_estimate(catenary: Catenary, settings: StaticSettings | None = None) -> tuple[int, float]:
    """Node count and a rough wall time of :func:`form_find` (0 s when the state is cached).

    Parameters
    ----------
    catenary : Catenary
        System model.
    settings : StaticSettings, optional
        Numerical settings (the element length sets the node count).

    Returns
    -------
    n_nodes : int
        Nodes of the discretisation. [-]
    seconds : float
        Expected time, from :data:`FORM_FIND_SECONDS`; an order of magnitude, not a promise. [s]
    """
    settings = settings or StaticSettings()
    n_nodes = discretise(catenary, settings).n_nodes
    if cache.active_directory() is not None and cache.contains(cache.state_key(catenary, settings)):
        return n_nodes, 0.0
    a, b, n_ref, power = FORM_FIND_SECONDS
    return n_nodes, a + b * (n_nodes / n_ref) ** power
