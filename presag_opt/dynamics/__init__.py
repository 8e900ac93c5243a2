"""The pantograph–catenary simulator: the catenary linearised about its static equilibrium, lumped
pantographs, penalty contact, HHT-α time integration, and the EN 50367 contact-force statistics.

Entry points
    :mod:`~presag_opt.dynamics.simulate` — :func:`~presag_opt.dynamics.simulate.simulate`, one run
    with its time histories (the readable reference engine, numba-free);
    :mod:`~presag_opt.dynamics.batch` — :func:`~presag_opt.dynamics.batch.simulate_many`, many
    operating points on one catenary (the compiled batch engine);
    :mod:`~presag_opt.dynamics.case` — the bundled simulation cases.
Inputs and results
    :mod:`~presag_opt.dynamics.settings` — numerics, analysis window, operating points;
    :mod:`~presag_opt.dynamics.numerics` — element length and time step from the speed;
    :mod:`~presag_opt.dynamics.run_plan` — one run's plan (start, window, duration, static contact);
    :mod:`~presag_opt.dynamics.results` — result types and the one run summary (``--json`` keys);
    :mod:`~presag_opt.dynamics.statistics` — filtered contact-force statistics.
Physics
    :mod:`~presag_opt.dynamics.laws` — contact, friction, dropper (tension only), pantograph
    suspension and the HHT-α constants, each defined once for every engine;
    :mod:`~presag_opt.dynamics.structure` — the catenary's M, C, K and droppers;
    :mod:`~presag_opt.dynamics.pantograph` — lumped-mass pantographs and their model files.
Single-run engine
    :mod:`~presag_opt.dynamics.integrator` — HHT-α / Newmark time stepping;
    :mod:`~presag_opt.dynamics.step_solvers` — the solvers of its Newton corrections (Woodbury on a factorised K_eff, or
    full refactorisation).
Batch engine (compiled)
    :mod:`~presag_opt.dynamics.batch` — the batch engine's package (its shared arrays, the compiled
    kernel and the parts of its Newton step).
"""
