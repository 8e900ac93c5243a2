"""Newmark / HHT-α integrator: analytic solutions, energy, dissipation, fast vs reference path."""

from __future__ import annotations

import time

import numpy as np
import pytest
import scipy.sparse as sp

from presag_opt.dynamics import laws
from presag_opt.dynamics.integrator import (
    IntegratorSettings,
    NonlinearForce,
    State,
    integrate,
)
from presag_opt.dynamics.pantograph import (
    FrictionRegularisation,
    Pantograph,
    load_pantograph,
)
from presag_opt.errors import ConvergenceError, ModelError


def _energy(mass: sp.spmatrix, stiffness: sp.spmatrix, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Kinetic plus strain energy of each row of u, v. [J]"""
    return 0.5 * np.einsum("ij,ij->i", v, (mass @ v.T).T) + 0.5 * np.einsum("ij,ij->i", u, (stiffness @ u.T).T)


def _spring_mass_chain(n: int) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Chain of n unequal masses and springs, fixed at one end, free at the other. [kg], [N/m]"""
    masses = 1.0 + 0.5 * np.sin(np.arange(n))
    springs = 2e4 * (1.0 + 0.3 * np.cos(np.arange(n)))
    incidence = sp.eye(n) - sp.eye(n, k=-1)
    return sp.diags(masses, format="csr"), (incidence.T @ sp.diags(springs) @ incidence).tocsr()


def test_average_acceleration_conserves_energy_of_undamped_chain():
    """Average-acceleration Newmark conserves ½vᵀMv + ½uᵀKu exactly for linear undamped free motion.

    The chain's highest mode has ω·Δt ≈ 0.6 at Δt = 2 ms. Required: within 0.1 % over 10 s. We assert
    1e-9 relative, the round-off level of 5000 steps, which the exact conservation allows.
    """
    mass, stiffness = _spring_mass_chain(30)
    u0 = 0.01 * np.linspace(0.0, 1.0, 30) ** 2
    result = integrate(
        mass, 0 * mass, stiffness, duration=10.0, initial_state=State(displacement=u0, velocity=np.zeros(30))
    )
    energy = _energy(mass, stiffness, result.displacement, result.velocity)
    assert np.max(np.abs(energy / energy[0] - 1.0)) < 1e-9


def test_hht_loses_energy_on_the_same_chain():
    """HHT-α (α = -0.1) must dissipate on that chain: more than 0.1 % in 10 s (the test above's bound)."""
    mass, stiffness = _spring_mass_chain(30)
    u0 = 0.01 * np.linspace(0.0, 1.0, 30) ** 2
    result = integrate(
        mass,
        0 * mass,
        stiffness,
        duration=10.0,
        settings=IntegratorSettings(scheme="hht", hht_alpha=-0.1),
        initial_state=State(displacement=u0, velocity=np.zeros(30)),
    )
    energy = _energy(mass, stiffness, result.displacement, result.velocity)
    assert energy[-1] / energy[0] < 1.0 - 1e-3


def _oscillator(frequency: float, time_step: float, duration: float, settings: IntegratorSettings | None = None):
    mass = 2.0
    stiffness = mass * (2.0 * np.pi * frequency) ** 2
    return integrate(
        sp.csr_matrix([[mass]]),
        sp.csr_matrix((1, 1)),
        sp.csr_matrix([[stiffness]]),
        duration=duration,
        settings=settings or IntegratorSettings(time_step=time_step),
        initial_state=State(displacement=np.array([0.1]), velocity=np.zeros(1)),
    )


def _zero_crossings(t: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Times where u changes sign, by linear interpolation. [s]"""
    i = np.nonzero(np.sign(u[:-1]) != np.sign(u[1:]))[0]
    return t[i] - u[i] * (t[i + 1] - t[i]) / (u[i + 1] - u[i])


def test_single_dof_matches_period_elongation_and_keeps_amplitude():
    """5 Hz oscillator at Δt = 10 ms (ω·Δt = 0.314): the discrete solution is A·cos(ω̄ t) with
    ω̄·Δt = 2·arctan(ω·Δt/2), i.e. a period 0.82 % longer than 2π/ω, and an exact amplitude.

    Tolerances: the measured period (from 20 zero crossings, interpolated linearly where the
    curvature vanishes) matches the formula within 1e-5, which separates it from the exact period by
    a factor of 800; u² + (v/ω)² stays A² to round-off (1e-12).

    References: T. J. R. Hughes, The Finite Element Method, Dover 2000, section 9.3.
    """
    frequency, dt, amplitude = 5.0, 0.01, 0.1
    result = _oscillator(frequency, dt, 2.0)
    omega = 2.0 * np.pi * frequency
    discrete_period = 2.0 * np.pi * dt / (2.0 * np.arctan(omega * dt / 2.0))
    crossings = _zero_crossings(result.time, result.displacement[:, 0])
    measured_period = 2.0 * np.mean(np.diff(crossings))
    assert measured_period == pytest.approx(discrete_period, rel=1e-5)
    assert measured_period / (1.0 / frequency) - 1.0 == pytest.approx(0.0082, abs=2e-4)
    radius = np.hypot(result.displacement[:, 0], result.velocity[:, 0] / omega)
    assert np.max(np.abs(radius / amplitude - 1.0)) < 1e-12


def _amplification_matrix(omega_dt: float, settings: IntegratorSettings) -> np.ndarray:
    """Matrix taking (u, v, a)_n to (u, v, a)_(n+1) for an undamped unit-mass oscillator, built by
    stepping once from each unit state. [-]"""
    omega = omega_dt / settings.time_step
    columns = []
    for state in np.eye(3):
        result = integrate(
            sp.identity(1, format="csr"),
            sp.csr_matrix((1, 1)),
            sp.csr_matrix([[omega**2]]),
            duration=settings.time_step,
            settings=settings,
            initial_state=State(displacement=state[:1], velocity=state[1:2], acceleration=state[2:]),
        )
        columns.append([result.displacement[-1, 0], result.velocity[-1, 0], result.acceleration[-1, 0]])
    return np.array(columns).T


@pytest.mark.parametrize("alpha", [-0.1, -1.0 / 3.0])
def test_hht_spectral_radius_at_high_frequency_is_the_theoretical_limit(alpha):
    """At ω·Δt = 1e4 the spectral radius of the HHT step tends to ρ∞ = (1 + α)/(1 - α) (0.818 for
    α = -0.1, 0.5 for α = -1/3); Newmark's is 1. Tolerance 1 %: at α = -1/3 the two principal roots
    meet as ω·Δt -> ∞ and approach ρ∞ only like (ω·Δt)^(-1/2) (0.3 % off at 1e4).

    References: Hilber, Hughes, Taylor (1977), doi:10.1002/eqe.4290050306.
    """
    dt = 2e-3
    hht = IntegratorSettings(time_step=dt, scheme="hht", hht_alpha=alpha, tolerance=1e-14)
    newmark = IntegratorSettings(time_step=dt, tolerance=1e-14)
    radius = np.max(np.abs(np.linalg.eigvals(_amplification_matrix(1e4, hht))))
    assert radius == pytest.approx((1.0 + alpha) / (1.0 - alpha), rel=0.01)
    assert np.max(np.abs(np.linalg.eigvals(_amplification_matrix(1e4, newmark)))) == pytest.approx(1.0, abs=1e-6)


def test_hht_removes_high_frequency_energy_and_keeps_low_frequency_energy():
    """Two uncoupled modes at Δt = 2 ms, 100 steps: ω·Δt = 1e4 and 0.0126 (1 Hz).

    HHT (α = -0.1) leaves less than 1e-6 of the high mode's energy (ρ∞^200 ≈ 4e-18, times the
    n² growth of its double root); the 1 Hz mode loses less than 0.1 % (damping ratio ≈ -α·ω·Δt/2).
    Newmark keeps the high mode's energy to 1e-7: recovering v from u - ũ at ω·Δt = 1e4 amplifies
    round-off by about (ω·Δt)²/4 = 2.5e7, i.e. to ~5e-9.
    """
    dt, steps = 2e-3, 100
    omegas = np.array([2.0 * np.pi, 1e4 / dt])
    start = State(displacement=np.array([0.1, 0.1]), velocity=np.zeros(2))
    energies = {}
    for scheme in ("newmark", "hht"):
        result = integrate(
            sp.identity(2, format="csr"),
            sp.csr_matrix((2, 2)),
            sp.diags(omegas**2, format="csr"),
            duration=steps * dt,
            settings=IntegratorSettings(time_step=dt, scheme=scheme, hht_alpha=-0.1),
            initial_state=start,
        )
        energies[scheme] = 0.5 * (result.velocity**2 + omegas**2 * result.displacement**2)
    newmark, hht = energies["newmark"], energies["hht"]
    assert np.max(np.abs(newmark[:, 1] / newmark[0, 1] - 1.0)) < 1e-7
    assert hht[-1, 1] / hht[0, 1] < 1e-6
    assert abs(hht[-1, 0] / hht[0, 0] - 1.0) < 1e-3


def _moving_contact_problem(n_wire_elements: int, pantograph: Pantograph, speed: float, uplift: float):
    """A pantograph running under a tensioned string with a wavy built-in profile.

    The string (20 kN, 1.35 kg/m, 0.25 m elements, both ends fixed) has DOFs 0..n-1, the pantograph
    n.. n+2 (head first). The head touches the wire through the unilateral penalty contact at the
    moving point x = 2 m + speed·t, interpolated linearly between wire nodes; the wire's built-in
    height 20 mm·sin(2πx/5 m) makes the head lose and regain contact.
    """
    h = 0.25
    length = n_wire_elements * h
    n = n_wire_elements - 1
    k = 20e3 / h
    wire_k = sp.diags([-k * np.ones(n - 1), 2 * k * np.ones(n), -k * np.ones(n - 1)], [-1, 0, 1])
    wire_m = sp.diags(1.35 * h * np.ones(n))
    mass = sp.block_diag([wire_m, pantograph.mass_matrix()], format="csr")
    damping = sp.block_diag([1e-4 * wire_k, pantograph.damping_matrix()], format="csr")
    stiffness = sp.block_diag([wire_k, pantograph.stiffness_matrix()], format="csr")
    panto = n + np.arange(pantograph.n_dofs)
    head = panto[pantograph.head_dof]
    regularisation = FrictionRegularisation(velocity=1e-3)

    def contact(u: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray, float, float]:
        x = 2.0 + speed * t
        element = int(x // h)
        xi = x / h - element
        nodes = np.array([element - 1, element])
        weights = np.array([1.0 - xi, xi])
        keep = (nodes >= 0) & (nodes < n)
        nodes, weights = nodes[keep], weights[keep]
        penetration = u[head] - weights @ u[nodes] - 0.02 * np.sin(2.0 * np.pi * x / 5.0)
        k = pantograph.contact.stiffness
        force, slope = laws.contact_force(k, penetration), laws.contact_tangent(k, penetration)
        return nodes, weights, float(force), float(slope)

    def forces(u: np.ndarray, v: np.ndarray, t: float) -> NonlinearForce:
        nodes, weights, force, slope = contact(u, t)
        gradient = np.concatenate([-weights, np.zeros(pantograph.n_dofs)])
        gradient[len(nodes) + pantograph.head_dof] = 1.0
        friction, friction_tangent = pantograph.friction_force(v[panto], regularisation)
        damping_block = np.zeros((len(gradient), len(gradient)))
        damping_block[len(nodes) :, len(nodes) :] = friction_tangent
        return NonlinearForce(
            dofs=np.concatenate([nodes, panto]),
            force=force * gradient + np.concatenate([np.zeros(len(nodes)), friction]),
            stiffness=slope * np.outer(gradient, gradient),
            damping=damping_block,
        )

    def external(t: float) -> np.ndarray:
        f = np.zeros(n + pantograph.n_dofs)
        f[panto[pantograph.uplift_dof]] = uplift
        return f

    duration = (length - 4.0) / speed
    return mass, damping, stiffness, forces, external, lambda t, u, v: contact(u, t)[2], head, duration


def test_fast_and_reference_paths_agree_on_moving_unilateral_contact():
    """The case-study pantograph (friction) at 25 m/s under a 40 m string with contact losses.

    Both paths solve the same equations to a residual of 1e-10 of the step's force scale, so the
    contact forces agree to about 1e-8 of their peak; we allow 1e-6 of the peak. Both are exact
    Newton methods (the fast one through the Woodbury identity), so their iterates agree to
    round-off and they take the same number of corrections, except where a residual lands within
    round-off of the tolerance: total counts within 1 %. The run must really switch contact on and
    off (between 5 % and 95 % of the time without contact).
    """
    pantograph = load_pantograph("case_study_2mass_friction")
    mass, damping, stiffness, forces, external, observe, head, duration = _moving_contact_problem(
        160, pantograph, speed=25.0, uplift=80.0
    )
    runs = {
        method: integrate(
            mass,
            damping,
            stiffness,
            duration=duration,
            settings=IntegratorSettings(method=method, scheme="hht", hht_alpha=-0.05),
            external_force=external,
            nonlinear_force=forces,
            observe=observe,
            record_dofs=[head],
        )
        for method in ("fast", "reference")
    }
    fast, reference = runs["fast"].observed[:, 0], runs["reference"].observed[:, 0]
    assert np.max(np.abs(fast - reference)) < 1e-6 * np.max(np.abs(reference))
    lost = np.mean(reference <= 0.0)
    assert 0.05 < lost < 0.95
    assert np.max(runs["fast"].iterations) > 1
    total = {method: int(np.sum(run.iterations)) for method, run in runs.items()}
    assert total["fast"] == pytest.approx(total["reference"], rel=0.01)


def test_stiff_force_with_wrong_tangent_raises_convergence_error():
    """A 1e9 N/m spring reported with a zero tangent makes the corrections diverge (the constant
    Newton matrix is ~1e6 N/m): the step must fail with the solver statistics, not return."""

    def hidden_spring(u: np.ndarray, v: np.ndarray, t: float) -> NonlinearForce:
        return NonlinearForce(dofs=np.array([0]), force=1e9 * u[:1], stiffness=np.zeros((1, 1)))

    with pytest.raises(ConvergenceError) as failure:
        integrate(
            sp.identity(1, format="csr"),
            sp.csr_matrix((1, 1)),
            sp.identity(1, format="csr"),
            duration=0.01,
            nonlinear_force=hidden_spring,
            initial_state=State(displacement=np.array([0.01]), velocity=np.zeros(1), acceleration=np.zeros(1)),
        )
    stats = failure.value.stats
    assert stats["step"] == 1
    assert stats["residual_history"][-1] > stats["residual_history"][0]


@pytest.mark.parametrize(
    ("settings", "message"),
    [
        ({"scheme": "rk4"}, "scheme = 'rk4'"),
        ({"method": "magic"}, "method = 'magic'"),
        ({"hht_alpha": -0.5}, r"hht_alpha = -0.5 - is outside the valid range \[-0.333333, 0\]"),
        ({"time_step": 0.0}, r"time_step = 0 ms is outside the valid range \[0.001, 100\] ms"),
        ({"max_iterations": 2.5}, "max_iterations = 2.5 is not a whole number"),
    ],
)
def test_bad_settings_are_model_errors(settings, message):
    with pytest.raises(ModelError, match=message):
        IntegratorSettings(**settings)


def test_singular_mass_without_initial_acceleration_is_a_model_error():
    with pytest.raises(ModelError, match="mass matrix is singular"):
        integrate(sp.csr_matrix((2, 2)), sp.csr_matrix((2, 2)), sp.identity(2, format="csr"), duration=0.01)


def _catenary_like_problem(n_nodes: int, pantograph: Pantograph, speed: float):
    """A banded two-wire system of 2·n_nodes DOFs: contact wire (tension, bending) and messenger wire
    coupled by droppers every 8 nodes, DOFs interleaved (bandwidth 3), plus the moving contact."""
    h = 0.25
    cw_k = 20e3 / h
    bending = 195.0 / h**3
    n = 2 * n_nodes
    rows, cols, vals = [], [], []

    def add(i: int, j: int, value: float) -> None:
        rows.append(i)
        cols.append(j)
        vals.append(value)

    for node in range(n_nodes):
        cw, mw = 2 * node, 2 * node + 1
        add(cw, cw, 2 * cw_k + 6 * bending)
        add(mw, mw, 2 * 16e3 / h)
        for offset, weight in ((1, -cw_k - 4 * bending), (2, bending)):
            if node + offset < n_nodes:
                add(cw, 2 * (node + offset), weight)
                add(2 * (node + offset), cw, weight)
        if node + 1 < n_nodes:
            add(mw, mw + 2, -16e3 / h)
            add(mw + 2, mw, -16e3 / h)
        if node % 8 == 4:
            for i, j, value in ((cw, cw, 1e5), (mw, mw, 1e5), (cw, mw, -1e5), (mw, cw, -1e5)):
                add(i, j, value)
    wire_k = sp.coo_matrix((vals, (rows, cols)), shape=(n, n)).tocsr()
    wire_m = sp.diags(np.tile([1.35 * h, 1.07 * h], n_nodes))
    mass = sp.block_diag([wire_m, pantograph.mass_matrix()], format="csr")
    damping = sp.block_diag([0.0125 * wire_m + 1e-4 * wire_k, pantograph.damping_matrix()], format="csr")
    stiffness = sp.block_diag([wire_k, pantograph.stiffness_matrix()], format="csr")
    head = n + pantograph.head_dof

    def forces(u: np.ndarray, v: np.ndarray, t: float) -> NonlinearForce:
        x = 1.0 + speed * t
        node = int(x // h)
        xi = x / h - node
        dofs = np.array([2 * node, 2 * node + 2, head])
        gradient = np.array([-(1.0 - xi), -xi, 1.0])
        penetration = gradient @ u[dofs] - 0.02 * np.sin(2.0 * np.pi * x / 5.0)
        force = float(laws.contact_force(pantograph.contact.stiffness, penetration))
        slope = float(laws.contact_tangent(pantograph.contact.stiffness, penetration))
        return NonlinearForce(dofs=dofs, force=force * gradient, stiffness=slope * np.outer(gradient, gradient))

    def external(t: float) -> np.ndarray:
        f = np.zeros(n + pantograph.n_dofs)
        f[n + pantograph.uplift_dof] = 120.0
        return f

    return mass, damping, stiffness, forces, external, head


@pytest.mark.slow
def test_benchmark_fast_path_on_10000_dofs():
    """Benchmark: 10 000-DOF banded system, EN 50318 pantograph at 70 m/s, 200 steps of 2 ms.

    The fast path must agree with the reference within 1 % of the peak head displacement and be
    faster; the speeds are printed (run with ``-m slow -s``).
    """
    pantograph = load_pantograph("en50318_2mass")
    mass, damping, stiffness, forces, external, head = _catenary_like_problem(5000, pantograph, speed=70.0)
    runs = {}
    for method in ("fast", "reference"):
        start = time.perf_counter()
        runs[method] = integrate(
            mass,
            damping,
            stiffness,
            duration=0.4,
            settings=IntegratorSettings(method=method),
            external_force=external,
            nonlinear_force=forces,
            record_dofs=[head],
        )
        elapsed = time.perf_counter() - start
        print(f"{method}: {runs[method].steps_per_second:.0f} steps/s ({elapsed:.2f} s with set-up)")
    fast, reference = runs["fast"].displacement[:, 0], runs["reference"].displacement[:, 0]
    assert np.max(np.abs(fast - reference)) < 0.01 * np.max(np.abs(reference))
    assert runs["fast"].steps_per_second > runs["reference"].steps_per_second
