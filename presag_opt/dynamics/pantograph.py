"""Lumped-mass pantographs and the penalty contact between pantograph head and contact wire.

A pantograph is a vertical chain of two or three lumped masses ("stages"), listed from the head (top,
DOF 0) down to the lowest frame mass. Each stage hangs on a spring, a viscous damper and, optionally,
a dry-friction element that connect it to the stage below; the lowest stage is connected the same way
to the car body, which is taken as fixed vertically. The static uplift force acts on the lowest stage
(:attr:`Pantograph.uplift_dof`); the contact force acts on the head.

The model describes motion about the static equilibrium: displacements are measured from it, z up,
uplift positive. The linear part is exposed as small dense matrices (M, C, K over the pantograph's own
DOFs); dry friction, the only nonlinearity inside the pantograph, is a separate force function with its
tangent, so that a simulator can hand it to :func:`presag_opt.dynamics.integrator.integrate`.

All values are SI inside these classes; model files may use kN/m and are converted on loading.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from presag_opt.dynamics import laws
from presag_opt.dynamics.assembly import force_contribution
from presag_opt.errors import ModelError
from presag_opt.system.components import Provenance
from presag_opt.system.loader import load_model_file, parse_section
from presag_opt.system.quantity import quantity, validate_fields

STEPS_PER_CONTACT_PERIOD = 10
"""Fewest time steps allowed per period of the head mass on the contact spring (see
:meth:`Pantograph.max_time_step`). [-]"""


@dataclass(frozen=True, kw_only=True)
class PantographStage:
    """One lumped mass of a pantograph and its suspension to the stage below (or the car body).

    Attributes
    ----------
    name : str
        Label, e.g. ``"head"`` or ``"frame"``.
    mass : float
        Lumped mass. [kg]
    stiffness : float
        Spring to the stage below (to the car body for the lowest stage). [N/m]
    damping : float
        Viscous damper in parallel with the spring. [N·s/m]
    friction : float
        Dry-friction force level in parallel with the spring (regularised Coulomb). [N]
    """

    name: str = ""
    mass: float = quantity("mass", 0.0, 200.0, low_open=True)
    stiffness: float = quantity("stiffness", 0.0, 1e6, default=0.0)
    damping: float = quantity("damping", 0.0, 1e4, default=0.0)
    friction: float = quantity("force", 0.0, 500.0, default=0.0)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise ModelError(f"name = {self.name!r} is not a string")
        validate_fields(self)


@dataclass(frozen=True, kw_only=True)
class PenaltyContact:
    """Unilateral penalty contact between the pantograph head and the contact wire.

    The contact force is ``stiffness * penetration`` while the head penetrates the wire
    (penetration = head height minus wire height at the contact point, both as displacements from
    the static contact position) and zero otherwise; in series with the wire element's compliance
    (:func:`~presag_opt.dynamics.laws.contact_force`). It pushes the wire up and the head down.

    Attributes
    ----------
    stiffness : float
        Penalty (contact) stiffness. [N/m]
    """

    stiffness: float = quantity("stiffness", 1.0, 1e4, display="kN/m", default=50e3)

    def __post_init__(self) -> None:
        validate_fields(self)


@dataclass(frozen=True, kw_only=True)
class FrictionRegularisation:
    """Numerical setting of the regularised Coulomb friction (not a physical parameter).

    The friction force is ``F0 * tanh(v_rel / velocity)``: the smaller ``velocity``, the closer to
    ideal Coulomb friction and the stiffer the equations. Show by a convergence study that results do
    not depend on it.

    Attributes
    ----------
    velocity : float
        Regularisation velocity. [m/s]
    """

    velocity: float = quantity("speed", 1e-6, 1.0, default=1e-3)

    def __post_init__(self) -> None:
        validate_fields(self)


@dataclass(frozen=True, kw_only=True)
class Pantograph:
    """A lumped-mass pantograph with two or three stages.

    Attributes
    ----------
    name : str
        Display name.
    stages : tuple of PantographStage
        The masses from the head (top, DOF 0) to the lowest frame mass.
    contact : PenaltyContact
        Contact model between the head and the contact wire.
    description : str
        Free text.
    provenance : dict
        Dotted model-file key -> :class:`~presag_opt.system.components.Provenance`.
    """

    name: str
    stages: tuple[PantographStage, ...]
    contact: PenaltyContact = field(default_factory=PenaltyContact)
    description: str = ""
    provenance: dict[str, Provenance] = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "stages", tuple(self.stages))
        if not 2 <= len(self.stages) <= 3:
            raise ModelError(f"stages: {len(self.stages)} given; a pantograph model has 2 or 3 stages (masses)")
        if not all(isinstance(s, PantographStage) for s in self.stages):
            raise ModelError("stages: every stage must be a PantographStage")

    @property
    def n_dofs(self) -> int:
        """Number of degrees of freedom (one vertical displacement per stage)."""
        return len(self.stages)

    @property
    def head_dof(self) -> int:
        """Local DOF of the head, where the contact force acts."""
        return 0

    @property
    def uplift_dof(self) -> int:
        """Local DOF of the lowest stage, where the static uplift force acts."""
        return self.n_dofs - 1

    def mass_matrix(self) -> np.ndarray:
        """Diagonal mass matrix over the pantograph DOFs. [kg]"""
        return np.diag([s.mass for s in self.stages])

    def stiffness_matrix(self) -> np.ndarray:
        """Stiffness matrix over the pantograph DOFs (car body fixed). [N/m]"""
        return self._connect([s.stiffness for s in self.stages])

    def damping_matrix(self) -> np.ndarray:
        """Viscous damping matrix over the pantograph DOFs (car body fixed). [N·s/m]"""
        return self._connect([s.damping for s in self.stages])

    @property
    def has_friction(self) -> bool:
        """Whether any stage has dry friction."""
        return any(s.friction > 0.0 for s in self.stages)

    def friction_force(
        self, velocity: np.ndarray, regularisation: FrictionRegularisation
    ) -> tuple[np.ndarray, np.ndarray]:
        """Regularised Coulomb friction forces and their velocity tangent.

        Stage i's friction element carries ``F0_i * tanh(dv_i / v_reg)``, where ``dv_i`` is its
        velocity relative to the stage below (to the car body for the lowest stage). The returned
        force is the internal force on the left-hand side of ``M a + C v + K u + f = f_ext``: it has
        the sign of the motion it resists.

        Parameters
        ----------
        velocity : numpy.ndarray
            Velocities of the pantograph DOFs, head first. [m/s]
        regularisation : FrictionRegularisation
            Numerical regularisation of the Coulomb law.

        Returns
        -------
        force : numpy.ndarray
            Friction force on each DOF. [N]
        tangent : numpy.ndarray
            Derivative of ``force`` with respect to ``velocity``, shape (n_dofs, n_dofs). [N·s/m]
        """
        velocity = np.asarray(velocity, dtype=float)
        force, tangent = np.zeros(self.n_dofs), np.zeros((self.n_dofs, self.n_dofs))
        piece_force, piece_tangent = np.empty(2), np.empty((2, 2))
        for stage, (upper, lower) in zip(self.stages, laws.suspension_elements(self.n_dofs)):
            relative = velocity[upper] - (velocity[lower] if lower >= 0 else 0.0)
            element_force, element_slope = laws.friction(stage.friction, relative, regularisation.velocity, 1.0)
            dofs = (upper, lower) if lower >= 0 else (upper,)
            force_contribution(element_force, element_slope, (1.0, -1.0)[: len(dofs)], piece_force, piece_tangent)
            for i, row in enumerate(dofs):
                force[row] += piece_force[i]
                for j, column in enumerate(dofs):
                    tangent[row, column] += piece_tangent[i, j]
        return force, tangent

    def contact_period(self) -> float:
        """Natural period of the head mass on the contact spring, 2π·sqrt(m_head / k_contact). [s]"""
        return 2.0 * math.pi * math.sqrt(self.stages[0].mass / self.contact.stiffness)

    def max_time_step(self) -> float:
        """Largest time step that resolves the contact oscillation. [s]

        The head bouncing on the penalty spring is the fastest motion the contact force shows; the
        head mass alone gives its highest frequency (wire mass taking part only lowers it). With
        :data:`STEPS_PER_CONTACT_PERIOD` = 10 steps per period, ω·Δt = 2π/10 and the
        average-acceleration Newmark period error (ω·Δt)²/12 is 3.3 %; larger steps misrepresent the
        contact force peaks (the scheme stays stable, so nothing else would warn).

        References
        ----------
        T. J. R. Hughes, *The Finite Element Method*, Dover 2000, section 9.3 (period error of the
        trapezoidal rule).
        """
        return self.contact_period() / STEPS_PER_CONTACT_PERIOD

    def check_time_step(self, time_step: float) -> None:
        """Raise ModelError if ``time_step`` is larger than :meth:`max_time_step`.

        Parameters
        ----------
        time_step : float
            Time step of the simulation. [s]
        """
        limit = self.max_time_step()
        if time_step > limit:
            raise ModelError(
                f"time_step = {time_step * 1e3:g} ms is too large for contact stiffness "
                f"{self.contact.stiffness / 1e3:g} kN/m on head mass {self.stages[0].mass:g} kg: use at most "
                f"{limit * 1e3:.3g} ms ({STEPS_PER_CONTACT_PERIOD} steps per contact period "
                f"{self.contact_period() * 1e3:.3g} ms)"
            )

    def _incidence(self) -> np.ndarray:
        """Rows: suspension elements (:func:`~presag_opt.dynamics.laws.suspension_elements`); relative
        velocity of element i = v_i - v_(i+1) (car body 0)."""
        incidence = np.zeros((self.n_dofs, self.n_dofs))
        for element, (upper, lower) in enumerate(laws.suspension_elements(self.n_dofs)):
            incidence[element, upper] = 1.0
            if lower >= 0:
                incidence[element, lower] = -1.0
        return incidence

    def _connect(self, coefficients: list[float]) -> np.ndarray:
        incidence = self._incidence()
        return incidence.T @ (np.asarray(coefficients)[:, None] * incidence)


PANTOGRAPH_SECTIONS = ("pantograph", "stages", "contact")


def load_pantograph(name_or_path: str | Path) -> Pantograph:
    """Load a pantograph model file (a path, or a built-in name such as ``en50318_2mass``).

    Parameters
    ----------
    name_or_path : str or pathlib.Path
        File path, or the name of a file in ``models/pantographs``.

    Returns
    -------
    Pantograph
        The validated model, with the provenance of every number.

    Raises
    ------
    ModelError
        For any malformed or out-of-range content; the message starts with the file name.
    """
    return load_model_file(name_or_path, "pantographs", pantograph_from_dict)


def pantograph_from_dict(data: Mapping[str, Any]) -> Pantograph:
    """Build a :class:`Pantograph` from the parsed content of a model file.

    Parameters
    ----------
    data : mapping
        Sections ``[pantograph]`` (name, description), ``[[stages]]`` (head first) and, optionally,
        ``[contact]``.

    Returns
    -------
    Pantograph
        The validated model.
    """
    unknown = [k for k in data if k not in PANTOGRAPH_SECTIONS]
    if unknown:
        raise ModelError(f"unknown section [{unknown[0]}]; valid sections: {', '.join(PANTOGRAPH_SECTIONS)}")
    for required in PANTOGRAPH_SECTIONS[:2]:
        if required not in data:
            raise ModelError(f"missing section [{required}]")
    header = data["pantograph"]
    if not isinstance(header, Mapping) or set(header) - {"name", "description"} or "name" not in header:
        raise ModelError("[pantograph] needs 'name' (and optionally 'description') and nothing else")
    tables = data["stages"]
    if not isinstance(tables, list):
        raise ModelError("stages: write each stage as a [[stages]] table, head first")
    provenance: dict[str, Provenance] = {}
    stages = tuple(
        parse_section(PantographStage, table, f"stages[{i}]", provenance) for i, table in enumerate(tables)
    )
    contact = (
        parse_section(PenaltyContact, data["contact"], "contact", provenance) if "contact" in data else PenaltyContact()
    )
    return Pantograph(
        name=str(header["name"]),
        description=str(header.get("description", "")),
        stages=stages,
        contact=contact,
        provenance=provenance,
    )
