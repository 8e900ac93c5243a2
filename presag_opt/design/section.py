"""Quasi-static pre-sag of a whole section: the elasticity of its analysed spans, S_rel per span.

On a section with unequal spans the relative pre-sag S_rel = S/l is computed per span and averaged
over the section, and the pre-sag built is S_rel,mean · l in every span (Swedish practice: pre-sag
proportional to span length; :class:`SectionPresag`). By default the two end spans, whose outer
support is the termination rather than a steady arm, are left out (:func:`default_spans`); an ideal
section is represented by its central span. The rule for one curve is in
:mod:`presag_opt.design.quasi_static`, the recommendation over a band in
:mod:`presag_opt.design.recommendation`.

References
----------
Schick, Liu, Stichel, "Validity range of a quasi-static method for adjusting the pre-sag of simple
railway catenary systems", Railway Sciences (2025), doi:10.1108/RS-05-2025-0016: section 5.1.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from presag_opt.design.quasi_static import check_method, elasticity_difference, interpolate_elasticities
from presag_opt.elasticity import METHODS as ELASTICITY_METHODS
from presag_opt.elasticity import ElasticityCurve, ElasticityStudy, elasticity_study
from presag_opt.errors import ConvergenceError, ModelError
from presag_opt.static.discretisation import StaticSettings
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import Catenary


def layout_kind(catenary: Catenary) -> str:
    """``"ideal"`` if all spans of the section are equally long, else ``"mixed"``."""
    return "ideal" if len(set(catenary.layout.span_lengths)) == 1 else "mixed"


def tension_label(catenary: Catenary) -> str:
    """The paper's label of a system by its tensions in kN, e.g. ``"9.8/9.8"``."""
    return f"{catenary.contact_wire.tension / 1e3:g}/{catenary.messenger_wire.tension / 1e3:g}"


@dataclass(frozen=True, kw_only=True)
class SectionPresag:
    """Quasi-static pre-sag of every analysed span of a section at one mean contact force.

    Attributes
    ----------
    catenary_name : str
        System and layout.
    mean_force : float
        F_m. [N]
    method : str
        ``"delta-e"`` or ``"mid-mast"``.
    spans : tuple of int
        Analysed spans, from 0. [-]
    span_lengths : ndarray
        Their lengths. [m]
    elasticity_difference : ndarray
        Δe or e_mid − e_mast of each span at F_m. [m/N]
    support_elasticity : ndarray
        Larger of the two support elasticities of each span at F_m. [m/N]

    References
    ----------
    Schick, Liu, Stichel (2025), doi:10.1108/RS-05-2025-0016, section 5.1 (S_rel per span, averaged
    over the section).
    """

    catenary_name: str
    mean_force: float
    method: str
    spans: tuple[int, ...]
    span_lengths: np.ndarray
    elasticity_difference: np.ndarray
    support_elasticity: np.ndarray

    @property
    def presag(self) -> np.ndarray:
        """Each span's own quasi-static pre-sag S_i = F_m · difference_i. [m]"""
        return self.mean_force * self.elasticity_difference

    @property
    def presag_rel(self) -> np.ndarray:
        """Each span's relative pre-sag S_i / l_i. [-]"""
        return self.presag / self.span_lengths

    @property
    def presag_rel_mean(self) -> float:
        """Mean of the spans' relative pre-sag: the section's S_rel. [-]"""
        return float(self.presag_rel.mean())

    @property
    def presag_proportional(self) -> np.ndarray:
        """Pre-sag to build in each span, proportional to its length: S_rel,mean · l_i. [m]"""
        return self.presag_rel_mean * self.span_lengths


@dataclass(frozen=True, kw_only=True)
class SectionElasticity:
    """Elasticity curves at force levels for the analysed spans of one section (one geometry).

    Attributes
    ----------
    catenary : Catenary
        System, layout and the pre-sag geometry the curves were computed at.
    studies : tuple of ElasticityStudy
        One per analysed span, each with the curves at ``force_levels``.
    force_levels : tuple of float
        Computed force levels. [N]
    elasticity_method : str
        ``"active-set"`` or ``"newton"`` (see :func:`presag_opt.elasticity.nonlinear_elasticity`).
    step : float
        Point spacing of the curves. [m]
    """

    catenary: Catenary
    studies: tuple[ElasticityStudy, ...]
    force_levels: tuple[float, ...]
    elasticity_method: str
    step: float

    @property
    def spans(self) -> tuple[int, ...]:
        """Analysed spans, from 0. [-]"""
        return tuple(s.span for s in self.studies)

    @property
    def span_lengths(self) -> np.ndarray:
        """Lengths of the analysed spans. [m]"""
        return np.array([self.catenary.layout.span_lengths[s] for s in self.spans])

    @property
    def layout_kind(self) -> str:
        """``"ideal"`` or ``"mixed"``."""
        return layout_kind(self.catenary)

    def curves_at(self, mean_force: float) -> tuple[ElasticityCurve, ...]:
        """Each analysed span's elasticity curve interpolated at ``mean_force``.

        Parameters
        ----------
        mean_force : float
            Mean contact force F_m. [N]
        """
        return self.curves_at_forces((mean_force,))[0]

    def curves_at_forces(self, mean_forces: Sequence[float]) -> list[tuple[ElasticityCurve, ...]]:
        """:meth:`curves_at` at each of ``mean_forces`` (each span's curves checked once).

        Parameters
        ----------
        mean_forces : sequence of float
            Mean contact forces F_m. [N]
        """
        per_span = [interpolate_elasticities(s.nonlinear, mean_forces) for s in self.studies]
        return list(zip(*per_span))

    def presag(self, mean_force: float, method: str = "delta-e") -> SectionPresag:
        """Quasi-static pre-sag of every analysed span at ``mean_force``.

        Parameters
        ----------
        mean_force : float
            F_m, inside the computed force levels. [N]
        method : {"delta-e", "mid-mast"}
            Variant of the rule.
        """
        check_method(method)
        return self._presag(mean_force, self.curves_at(mean_force), method)

    def _presag(self, mean_force: float, curves: Sequence[ElasticityCurve], method: str) -> SectionPresag:
        return SectionPresag(
            catenary_name=self.catenary.name,
            mean_force=float(mean_force),
            method=method,
            spans=self.spans,
            span_lengths=self.span_lengths,
            elasticity_difference=np.array([elasticity_difference(c, method) for c in curves]),
            support_elasticity=np.array([max(c.elasticity[0], c.elasticity[-1]) for c in curves]),
        )

    def presag_rel_curve(self, mean_forces: Sequence[float], method: str = "delta-e") -> np.ndarray:
        """The section's S_rel (mean over spans) at each mean force. [-]

        Parameters
        ----------
        mean_forces : sequence of float
            Mean contact forces F_m. [N]
        method : {"delta-e", "mid-mast"}
            Pre-sag variant (see :meth:`SectionElasticity.presag`).
        """
        return self.presag_rel_curves(mean_forces, (method,))[method]

    def presag_rel_curves(self, mean_forces: Sequence[float], methods: Sequence[str]) -> dict[str, np.ndarray]:
        """:meth:`presag_rel_curve` of several variants from one interpolation of the curves. [-]

        Parameters
        ----------
        mean_forces : sequence of float
            Mean contact forces F_m. [N]
        methods : sequence of str
            Pre-sag variants, each ``"delta-e"`` or ``"mid-mast"``.
        """
        for method in methods:
            check_method(method)
        curves = self.curves_at_forces(mean_forces)
        return {m: np.array([self._presag(f, c, m).presag_rel_mean for f, c in zip(mean_forces, curves)])
                for m in methods}


def check_elasticity_method(elasticity_method: str) -> str:
    """Return ``elasticity_method`` if the elasticity module knows it, else raise ModelError."""
    if elasticity_method not in ELASTICITY_METHODS:
        raise ModelError(f"elasticity_method = {elasticity_method!r} is not one of {', '.join(ELASTICITY_METHODS)}")
    return elasticity_method


def default_spans(catenary: Catenary) -> tuple[int, ...]:
    """Spans whose pre-sag is sized by default, from 0.

    An ideal section (identical spans, the paper's "ideal spans"): its central span, away from
    the terminations. A mixed section: every span except the first and the last. The paper averages
    S_rel over its whole representative section, but in our model the outer support of an end span
    is the balance-weight termination, not a steady arm: its elasticity there is about three times
    a steady arm's (1.05 against 0.36 mm/N on ST 9,8/9,8), which would inflate those spans' S_rel by
    about half and dominate the static uplift estimate. In service these are overlap spans, whose
    geometry is designed separately.
    """
    n = catenary.layout.n_spans
    if layout_kind(catenary) == "ideal":
        return (catenary.layout.central_span,)
    return tuple(range(1, n - 1))


def section_elasticity(
    system: Catenary | EquilibriumState,
    *,
    force_levels: Sequence[float],
    spans: Sequence[int] | None = None,
    step: float = 0.5,
    elasticity_method: str = "active-set",
    settings: StaticSettings | None = None,
    progress: Callable[[str], None] | None = None,
) -> SectionElasticity:
    """Form-find a section once and compute the elasticity curves of its spans at force levels.

    Parameters
    ----------
    system : Catenary or EquilibriumState
        System model (form-found here; its ``presag_rel`` is the geometry the elasticity is
        computed at), or a form-found state to reuse.
    force_levels : sequence of float
        Force levels. [N]
    spans : sequence of int, optional
        Spans to analyse, from 0. Default (:func:`default_spans`): the central span of an ideal
        section, every span but the two end spans of a mixed one. [-]
    step : float
        Point spacing of the curves. [m]
    elasticity_method : {"active-set", "newton"}
        Method of the nonlinear curves; ``"active-set"`` is the fast one for whole sections.
    settings : StaticSettings, optional
        Numerical settings of the static model (form-finding only; a given state keeps its own).
    progress : callable, optional
        Called with a short message before each expensive step.

    Returns
    -------
    SectionElasticity
    """
    levels = tuple(sorted({float(f) for f in force_levels}))
    if not levels:
        raise ModelError("force_levels is empty; give at least one force level in N")
    check_elasticity_method(elasticity_method)
    catenary = system.catenary if isinstance(system, EquilibriumState) else system
    n_spans = catenary.layout.n_spans
    spans = default_spans(catenary) if spans is None else tuple(spans)
    for s in spans:
        if not 0 <= s < n_spans:
            raise ModelError(f"span = {s + 1} is outside the valid range [1, {n_spans}]")
    if isinstance(system, EquilibriumState):
        state = system
    else:
        if progress:
            progress(f"{catenary.name}: form-finding")
        state = form_find(catenary, settings)
    studies = []
    for i, span in enumerate(spans):
        if progress:
            progress(f"{catenary.name}: elasticity of span {i + 1}/{len(spans)}")
        studies.append(elasticity_study(state, span=span, forces=levels, step=step, method=elasticity_method))
    return SectionElasticity(
        catenary=catenary,
        studies=tuple(studies),
        force_levels=levels,
        elasticity_method=elasticity_method,
        step=step,
    )


def section_curves(state: EquilibriumState, levels, step: float) -> SectionElasticity:
    """Elasticity curves of every span of a form-found section: active-set, Newton where it cannot settle.

    The active-set method solves the structure linearised about the unloaded equilibrium with
    tension-only droppers. Next to a push-off arm that linearisation can lose its stability: the
    compressed arm's geometric stiffness across it is negative, −C·cos²θ/L (an inverted pendulum),
    and once the uplift slackens the droppers next to the mast, the contact wire there is held only
    by its tension over the distance to the next taut droppers, T·(1/a + 1/b); where that is less than
    C/L (e.g. 645 N on a 1 m arm, ST 7,1/7,1 on a 500 m curve with 45 m spans) the linearised problem
    has no stable solution and its slack set cycles. The span is then computed by the geometrically
    nonlinear Newton method (the arm's rotation and the wire's stretch in the equations; each contact
    position starts from the previous one's equilibrium, a continuation along the span), which finds the
    equilibrium where one exists; where it does not, the arm flips under the
    load, and the error names the mast, the arm force and the load.

    Parameters
    ----------
    state : EquilibriumState
        The section form-found.
    levels : sequence of float
        Force levels. [N]
    step : float
        Point spacing of the curves. [m]

    Raises
    ------
    ModelError
        No equilibrium under a force level in a span next to a push-off arm (the arm would flip).
    """
    catenary = state.catenary
    studies, fallback = [], []
    for span in range(catenary.layout.n_spans):
        try:
            studies.append(elasticity_study(state, span=span, forces=levels, step=step, method="active-set"))
            continue
        except ConvergenceError:
            fallback.append(span)
        try:
            studies.append(elasticity_study(state, span=span, forces=levels, step=step, method="newton"))
        except ConvergenceError as exc:
            push = np.flatnonzero(catenary.mast_push_off())
            arms = [m for m in (span, span + 1) if m in set(push)] or list(push)
            forces = state.steady_arm_forces()
            names = ", ".join(f"mast {m + 1} ({-forces[m]:.0f} N of compression)" for m in arms) or "none"
            raise ModelError(
                f"span {span + 1}: no equilibrium under an uplift up to {max(levels):g} N; push-off arm(s) at {names}: "
                "the compressed arm would flip once the droppers next to it go slack (its negative stiffness C/L exceeds "
                "the wire's); use a pull-off arm there, a longer arm, or shorter spans") from exc
    return SectionElasticity(catenary=catenary, studies=tuple(studies), force_levels=tuple(sorted(levels)),
                             elasticity_method="newton" if fallback else "active-set", step=step)
