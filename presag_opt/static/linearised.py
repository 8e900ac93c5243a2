"""The unloaded structure linearised about an equilibrium, with its droppers tension-only.

:class:`TensionOnlyStructure` solves (K − G_S D_S G_Sᵀ) q = p + G_S f0_S for the displacements q under
extra loads p, with S the set of slack droppers: the tangent stiffness K at the equilibrium, G the
droppers' length gradients, D their stiffnesses and f0 their preloads. One factorisation of K and
W = K⁻¹ G serve every load through the Woodbury identity
(:func:`~presag_opt.static.woodbury.woodbury_update`, shared with the dynamics' Newton correction); S is found by the active-set iteration (a
dropper whose force would drop below zero is removed, a removed one that would stretch again comes
back). Geometric nonlinearity is left out; the full nonlinear equilibrium is
:meth:`~presag_opt.static.equilibrium.EquilibriumState.solve`.

The elasticity's active-set method (:mod:`presag_opt.elasticity`) and the dynamic model's static
response (:mod:`presag_opt.dynamics.structure`) both solve this problem here. The dropper's law,
:func:`dropper_axial_force` with its slack threshold :func:`dropper_slack`, is defined here once for
the statics and every dynamic engine (:mod:`presag_opt.dynamics.laws`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from presag_opt.errors import ConvergenceError
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.static.woodbury import woodbury_update


def dropper_axial_force(preload, stiffness, stretch, rate, rayleigh_beta):
    """Axial force of a linearised dropper, N = N0 + k e + β_R k ė (tension positive). [N]

    Works on numbers and on arrays of droppers alike; the damping part is left out when β_R = 0
    (statics: pass 0 for ``rate`` and ``rayleigh_beta``).

    Parameters
    ----------
    preload : float or ndarray
        Static force N0. [N]
    stiffness : float or ndarray
        Axial stiffness k. [N/m]
    stretch : float or ndarray
        Stretch e from the equilibrium, e·(Δu_MW − Δu_CW) with e the unit vector along the dropper. [m]
    rate : float or ndarray
        Stretch rate ė. [m/s]
    rayleigh_beta : float
        Stiffness-proportional Rayleigh coefficient β_R of the structure. [s]
    """
    axial = preload + stiffness * stretch
    if rayleigh_beta != 0.0:
        axial = axial + rayleigh_beta * stiffness * rate
    return axial


def dropper_directions(state: EquilibriumState) -> np.ndarray:
    """Unit vector e of every dropper, from node a to node b of its axial element, at
    the equilibrium ``state``, shape (n_droppers, 3) [-]: the direction its stretch is measured along
    (here and in the dynamic model's droppers, :mod:`presag_opt.dynamics.structure`).

    Parameters
    ----------
    state : EquilibriumState
        The equilibrium the droppers are linearised about.
    """
    axial, drops = state.discretisation.axial, state.discretisation.dropper_elements
    chord = state.positions[axial.node_b[drops]] - state.positions[axial.node_a[drops]]
    return chord / np.linalg.norm(chord, axis=1)[:, None]


def dropper_slack(axial):
    """Whether a tension-only dropper is slack: its axial force below zero (its axial part removed).

    Parameters
    ----------
    axial : float or ndarray
        Axial force of the linearised dropper (:func:`dropper_axial_force`). [N]
    """
    return axial < 0.0


@dataclass(frozen=True)
class TensionOnlyStructure:
    """The structure linearised about an equilibrium, droppers as tension-only constraints.

    Attributes
    ----------
    state : EquilibriumState
        The (unloaded) equilibrium linearised about.
    gradients : ndarray, shape (free DOFs, droppers)
        Length gradient G of every dropper on the free DOFs. [-]
    influence : ndarray, shape (free DOFs, droppers)
        W = K⁻¹ G. [m/N]
    gram : ndarray, shape (droppers, droppers)
        Gᵀ K⁻¹ G. [m/N]
    preload : ndarray
        Static dropper forces f0. [N]
    stiffness : ndarray
        Axial dropper stiffnesses D. [N/m]
    """

    state: EquilibriumState
    gradients: np.ndarray
    influence: np.ndarray
    gram: np.ndarray
    preload: np.ndarray
    stiffness: np.ndarray

    @classmethod
    def of(cls, state: EquilibriumState) -> TensionOnlyStructure:
        """The linearised structure of a state (built once and kept with the state).

        Parameters
        ----------
        state : EquilibriumState
            Equilibrium with every dropper in tension.
        """
        if state.memo.tension_only is None:
            disc = state.discretisation
            free = state.model.functions.free_dofs
            drops = disc.dropper_elements
            ax = disc.axial
            d = dropper_directions(state)
            full = np.zeros((disc.n_dofs, len(drops)))
            cols = np.arange(len(drops))
            for c in range(3):
                full[3 * ax.node_b[drops] + c, cols] = d[:, c]
                full[3 * ax.node_a[drops] + c, cols] = -d[:, c]
            gradients = full[free]
            influence = state.factorised_stiffness().solve(gradients)
            state.memo.tension_only = cls(
                state=state,
                gradients=gradients,
                influence=influence,
                gram=gradients.T @ influence,
                preload=state.dropper_forces(),
                stiffness=state.params.axial_stiffness[drops],
            )
        return state.memo.tension_only

    def slack_set(
        self, load_stretch: np.ndarray, slack: np.ndarray | None = None, *, max_iterations: int | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """The slack droppers under a load, and the correction of the slack droppers' forces.

        Parameters
        ----------
        load_stretch : ndarray
            Gᵀ K⁻¹ p: every dropper's stretch under the load with all droppers taut. [m]
        slack : ndarray of bool, optional
            Slack set to start the iteration from (a neighbouring load's, for speed); default none.
        max_iterations : int, optional
            Active-set iterations allowed; default 4 per dropper plus 10. [-]

        Returns
        -------
        slack : ndarray of bool
            The slack droppers.
        correction : ndarray
            z = (D_S⁻¹ − G_Sᵀ K⁻¹ G_S)⁻¹ G_Sᵀ q0, one per slack dropper, with q0 = K⁻¹ (p + G_S f0_S);
            the displacement is q0 + W_S z. [N]

        Raises
        ------
        ConvergenceError
            If the set of slack droppers does not settle.
        """
        f0, k, gram = self.preload, self.stiffness, self.gram
        slack = np.zeros(len(f0), dtype=bool) if slack is None else slack
        iterations = 4 * len(f0) + 10 if max_iterations is None else max_iterations
        for _ in range(iterations):
            s = np.flatnonzero(slack)
            # q0 = K^-1 (p + G_S f0_S); y = G_S^T q0
            stretch0 = load_stretch + gram[:, s] @ f0[s]
            if len(s):
                # Woodbury with C = −D_S: y = (G_SᵀK⁻¹G_S − D_S⁻¹)⁻¹ G_Sᵀ q0 = −z, stretch0 − Gᵀ W_S y
                stretch, y = woodbury_update(stretch0, gram[:, s], gram[np.ix_(s, s)] - np.diag(1.0 / k[s]), stretch0[s],
                                             singular="tension-only droppers: the slack droppers' Woodbury system is "
                                                      "singular (a slack dropper's stiffness cancels the structure's)")
                z = -y
            else:
                z, stretch = np.zeros(0), stretch0
            new_slack = dropper_slack(dropper_axial_force(f0, k, stretch, 0.0, 0.0))
            if np.array_equal(new_slack, slack):
                return slack, z
            slack = new_slack
        raise ConvergenceError(
            f"tension-only droppers: the set of slack droppers did not settle in {iterations} iterations",
            {"slack_droppers": int(slack.sum()), "iterations": iterations},
        )

    def displacement(self, load: np.ndarray, *, max_iterations: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Displacements from the equilibrium under extra loads, and the slack droppers.

        Parameters
        ----------
        load : ndarray, shape (free DOFs,)
            Nodal forces on the free DOFs. [N]
        max_iterations : int, optional
            Active-set iterations allowed (see :meth:`slack_set`). [-]

        Returns
        -------
        displacement : ndarray
            q on the free DOFs. [m]
        slack : ndarray of bool
            The slack droppers.
        """
        slack, z = self.slack_set(self.influence.T @ load, max_iterations=max_iterations)
        s = np.flatnonzero(slack)
        q = self.state.factorised_stiffness().solve(load) + self.influence[:, s] @ (self.preload[s] + z)
        return q, slack
