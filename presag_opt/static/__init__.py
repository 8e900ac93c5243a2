"""The static model of a catenary section: discretisation, potential energy, equilibrium, form-finding.

Modules, from the bottom up:

discretisation
    :class:`StaticSettings` and :func:`discretise`: nodes, axial elements, bending triples, springs
    and loads of a :class:`~presag_opt.system.catenary.Catenary` (SI units throughout).
banded_solver
    :class:`BandedSolver`: the track-wise ordering of a stiffness pattern and its factorisation
    (banded Cholesky, SuperLU when not positive definite); many right-hand sides go to
    :mod:`presag_opt.native.banded` with an explicit back-end.
potential
    The problem: the total potential energy of a discretisation (CasADi element functions mapped
    over all elements) with its gradient and tangent stiffness, :class:`PhysicalParameters`.
newton
    Newton's method on the potential (droppers free to go slack) to the force tolerance.
equilibrium
    :class:`EquilibriumState` (a solved state, with its :class:`StateMemo`), :class:`StaticModel`,
    :func:`lone_wire_state`.
form_finding_equations
    The form-finding equations g(v; p) = 0 (CasADi SX) and their sensitivity to the target heights.
form_finding_solver
    Their solve with IPOPT (the method and its options).
form_finding
    :func:`form_find`: the passes (IPOPT, then a Newton relaxation), the checks, the cache;
    :func:`dropper_height_sensitivity`.
cache
    The on-disk cache of form-found states (keys, reading and writing a state's arrays).
run_time
    :func:`form_find_estimate`: a rough wall time of form-finding.
linearised
    :class:`TensionOnlyStructure`: the structure linearised about a state with tension-only droppers.
"""
