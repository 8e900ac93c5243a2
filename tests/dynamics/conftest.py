"""Shared pieces of the batch-engine tests: the case study and its form-found 5-span section."""

from __future__ import annotations

import pytest

from presag_opt.dynamics.case import load_case
from presag_opt.static.form_finding import form_find
from presag_opt.system.catenary import SpanLayout


@pytest.fixture(scope="session")
def case():
    return load_case("case_study_st98")


@pytest.fixture(scope="session")
def short_state(case):
    """Form-found 5-span ST 9,8/9,8 section (one lead-in span each side of the analysed central span)."""
    catenary = case.catenary.with_layout(SpanLayout(span_lengths=(60.0,) * 5, label="5 ideal spans"))
    return form_find(catenary, case.settings.static)


def _synthetic_batch(head_height: float = 2e-3, tolerance: float = 1e-10, max_iterations: int = 20):
    """A one-run batch on a synthetic system small enough to check by hand: 6 catenary DOFs (K_eff
    tridiagonal), a 2-stage pantograph (DOFs 6 = head, 7), its two friction elements, one dropper on
    DOFs 0–5, the head under the wire nodes 2 and 3 (weights ½). Returns the kernel's named tuples
    and the dense K_eff of the catenary (``k_cat``) and of the pantograph (``k_pan``)."""
    from types import SimpleNamespace

    import numpy as np

    from presag_opt.dynamics.batch import kernel_data as kd
    from presag_opt.dynamics.batch.band_rows import lower_rows, symmetric_rows, upper_rows
    from presag_opt.dynamics.laws import scheme_constants

    n, n_p = 6, 2
    # K_eff = a0 M + s (K + a1 C) [N/m], SPD, dominated by a0 M as at a 1 ms step (a0 ≈ 3.3e6 1/s²)
    k_cat = 7e6 * np.eye(n) - 1e5 * (np.eye(n, k=1) + np.eye(n, k=-1))
    k_pan = np.array([[2.3e7, -1e5], [-1e5, 4e7]])
    inverse = np.linalg.inv(k_cat)
    band = np.zeros((n, 2))
    band[:, 0] = np.diag(k_cat)
    band[:-1, 1] = np.diag(k_cat, -1)
    factor = np.linalg.cholesky(k_cat)
    factor_band = np.zeros((n, 2))
    factor_band[:, 0] = np.diag(factor)
    factor_band[:-1, 1] = np.diag(factor, -1)
    dropper_dofs = np.arange(6, dtype=np.int64)[None, :]
    gradient = np.array([[0.6, 0.0, 0.8, -0.6, 0.0, -0.8]])
    columns = np.ascontiguousarray(inverse.T)  # row c: K⁻¹ e_c
    shared = kd.Shared(
        stiffness_band=band, factor_band=factor_band, stiffness_rows=symmetric_rows(band),
        lower_rows=lower_rows(factor_band), upper_rows=upper_rows(factor_band), mass=np.full(n, 2.0),
        pantograph_mass=np.array([7.0, 12.0]), pantograph_damping=np.array([[20.0, -20.0], [-20.0, 50.0]]),
        pantograph_stiffness=np.array([[800.0, -800.0], [-800.0, 1500.0]]), pantograph_inverse=np.linalg.inv(k_pan),
        column_of=np.arange(n, dtype=np.int64), columns=columns, head_dof=np.array([6], dtype=np.int64),
        contact_stiffness=np.array([5e4]), friction_dofs=np.array([[6, 7], [7, -1]], dtype=np.int64),
        friction_levels=np.array([5.0, 10.0]), dropper_dofs=dropper_dofs, dropper_gradient=gradient,
        dropper_stiffness=np.array([1e5]), dropper_recorded=np.array([True]),
        support_dofs=np.array([0], dtype=np.int64),
        stretch_influence=np.ascontiguousarray(np.einsum("cdk,dk->cd", columns[:, dropper_dofs], gradient)),
        candidate_index=np.arange(n, dtype=np.int64), candidate_rows=np.arange(n, dtype=np.int64),
        support_row=np.eye(n, dtype=np.bool_)[0],
    )
    steps = 3
    runs = kd.Runs(
        n_steps=np.array([steps], dtype=np.int64),
        path_nodes=np.tile(np.array([2, 3], dtype=np.int64), (1, 1, steps + 1, 1)),
        path_weights=np.full((1, 1, steps + 1, 2), 0.5), path_compliance=np.full((1, 1, steps + 1), 1e-6),
        head_height=np.array([[head_height]]), uplift=np.array([40.0]),
        cw_height=np.zeros((1, n)), dropper_preload=np.array([[100.0]]),
    )
    rng = np.random.default_rng(7)
    state = kd.RunState(
        u=1e-3 * rng.normal(size=(n, 1)), v=1e-2 * rng.normal(size=(n, 1)), q=np.zeros((n, 1)),
        r=10.0 * rng.normal(size=(n, 1)), pantograph_u=1e-3 * rng.normal(size=(n_p, 1)),
        pantograph_v=1e-2 * rng.normal(size=(n_p, 1)), pantograph_a=0.1 * rng.normal(size=(n_p, 1)),
        pantograph_r=10.0 * rng.normal(size=(n_p, 1)),
    )
    out = kd.Records(contact_force=np.zeros((1, 1, steps + 1)), uplift_max=np.zeros(1), slack_max=np.zeros(1, np.int64),
                     status=np.full(1, kd.STATUS_RUNNING, np.int64), fail_step=np.zeros(1, np.int64),
                     fail_residual=np.zeros(1), iterations=np.zeros(1, np.int64))
    scheme = scheme_constants(SimpleNamespace(scheme="hht", hht_alpha=-0.1, time_step=1e-3))
    scalars = kd.Scalars(scheme=scheme, rayleigh_alpha=0.1, rayleigh_beta=1e-4, tolerance=tolerance,
                         max_iterations=max_iterations, friction_velocity=0.01)
    work = kd.make_work(shared, 1)
    work.g[:, 0] = 50.0 * rng.normal(size=n)  # the sweeps' g on the (all candidate) rows [N]
    work.delta[:, 0] = inverse @ work.g[:, 0]  # and δ_lin = K_eff⁻¹ g [m]
    return SimpleNamespace(scalars=scalars, shared=shared, runs=runs, state=state, out=out, work=work,
                           scratch=kd.make_scratch(shared), k_cat=k_cat, k_pan=k_pan, n=n, n_p=n_p)


@pytest.fixture
def synthetic_batch():
    """Factory of the one-run synthetic batch (:func:`_synthetic_batch`; keyword arguments passed on)."""
    return _synthetic_batch


PLAIN_PARTS = ("forces", "predictor", "woodbury", "update", "newton_step")
"""The batch kernel's parts that :func:`plain_parts` imports as plain Python."""


@pytest.fixture(scope="session")
def plain_parts():
    """The parts of the batch kernel's Newton step (:mod:`presag_opt.dynamics.batch.newton_step` and
    the modules it is made of) as plain Python: their modules imported a second time with numba's
    jit off, so that every ``kernel_part`` function is the function as written. The kernel compiles the
    same source; the synthetic tests call the parts here in milliseconds (compiled, a part has no Python
    entry point). The compiled kernel itself is
    checked end to end (``batch/test_simulation.py``: the batch against the single-run engine).
    The compiled modules stay as they were, in ``sys.modules`` and on their package."""
    import importlib
    import sys
    from types import SimpleNamespace

    from numba.core import config

    import presag_opt.dynamics.batch as package

    names = [f"{package.__name__}.{part}" for part in PLAIN_PARTS]
    saved_modules = {name: sys.modules.pop(name) for name in names if name in sys.modules}
    saved_attributes = {part: getattr(package, part) for part in PLAIN_PARTS if hasattr(package, part)}
    jit_was_off = config.DISABLE_JIT
    config.DISABLE_JIT = True
    try:
        plain = {part: importlib.import_module(name) for part, name in zip(PLAIN_PARTS, names)}
    finally:
        config.DISABLE_JIT = jit_was_off
        for name in names:
            sys.modules.pop(name, None)
        sys.modules.update(saved_modules)
        for part in PLAIN_PARTS:
            if part in saved_attributes:
                setattr(package, part, saved_attributes[part])
            elif hasattr(package, part):
                delattr(package, part)
    assert not hasattr(plain["newton_step"].newton_step, "py_func"), "numba compiled a plain part"
    return SimpleNamespace(**plain)
