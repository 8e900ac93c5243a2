"""``presag simulate``: JSON and plot output against the API, case files, and one-line errors."""

from __future__ import annotations

import json
import re

import pytest

from presag_opt.cli import main
from presag_opt.dynamics.case import load_case
from presag_opt.dynamics.pantograph import load_pantograph
from presag_opt.dynamics.simulate import simulate

REQUIRED_KEYS = (
    "Fm_N", "sigma_N", "sigma_over_Fm", "stat_max_N", "stat_min_N", "max_N", "min_N",
    "loss_of_contact_pct", "uplift_max_mm", "beta",
)

PANTOGRAPH_FILE = """
[pantograph]
name = "no frame mass"

[[stages]]
name = "head"
mass = { value = 7.2, unit = "kg", source = "assumed" }
stiffness = { value = 4200, unit = "N/m", source = "assumed" }

[[stages]]
name = "frame"
damping = { value = 90, unit = "N*s/m", source = "assumed" }
"""


def _run(capsys, *args: str) -> tuple[int, str, str]:
    code = main(["simulate", *args])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.mark.slow  # keeps the default run under 5 minutes; the batch tests cover the same path
def test_json_and_plot_match_the_api_in_user_units(capsys, tmp_path, st98):
    """The command line converts km/h and N/(km/h)² to SI and calls simulate(): its JSON equals the
    API's statistics for the same inputs (form-finding and integration are deterministic; 1e-9)."""
    plot = tmp_path / "figs"
    code, out, _ = _run(
        capsys, "st_9.8_ideal", "--pantograph", "case_study_2mass_friction", "--speed", "180",
        "--static-force", "120", "--aero", "0.00097", "--json", "--plot", str(plot),
    )
    assert (plot / "contact_force.png").stat().st_size > 10_000
    assert code == 0
    printed = json.loads(out)
    assert set(REQUIRED_KEYS) <= set(printed)
    api = simulate(
        st98, load_pantograph("case_study_2mass_friction"), speed=50.0, static_force=120.0,
        aero_coefficient=0.00097 * 3.6**2,
    ).to_dict()
    for key in REQUIRED_KEYS:
        assert printed[key] == pytest.approx(api[key], rel=1e-9, abs=1e-9), key
    assert printed["speed_kmh"] == pytest.approx(180.0, rel=1e-12)
    assert printed["aero_force_N"] == pytest.approx(0.00097 * 180.0**2, rel=1e-12)
    assert printed["analysed_spans"] == [5, 6]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--case", "en50318_2002", "--speed", "450"],
         r"speed = 450 km/h is outside the valid range \[0, 438.1\d*\) km/h"),
        (["st_9.8_ideal", "--pantograph", "en50318_2mass", "--speed", "90", "--static-force", "0"],
         r"static_force = 0 N is outside the valid range \(0, 500\] N"),
        (["st_9.8_ideal", "--pantograph", "en50318_2mass", "--speed", "90", "--static-force", "100",
          "--time-step", "10"], r"time_step = 10 ms is too large for contact stiffness 50 kN/m"),
        (["st_9.8_ideal", "--speed", "90"], r"--pantograph, --static-force required with a catenary MODEL"),
        (["st_9.8_ideal", "--case", "en50318_2002"], r"give either a catenary MODEL or --case, not both"),
        (["--case", "no_such_case"], r"model 'no_such_case' is neither a file nor a built-in case model"),
        (["--case", "en50318_2002", "--aero", "-0.001"], r"aero_coefficient = -0.001 N/\(km/h\)\^2 is outside"),
    ],
)
def test_bad_input_ends_with_one_line_and_status_2(capsys, args, message):
    """Errors come before form-finding: each call returns at once."""
    code, out, err = _run(capsys, *args)
    assert code == 2
    assert out == ""
    assert err.count("\n") == 1 and err.startswith("presag: error: ")
    assert re.search(message, err), err


def test_pantograph_file_with_a_missing_field_is_a_one_line_error(capsys, tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text(PANTOGRAPH_FILE, encoding="utf-8")
    code, _, err = _run(capsys, "st_9.8_ideal", "--pantograph", str(path), "--speed", "90", "--static-force", "100")
    assert code == 2
    assert "broken.toml: [stages[1]]: missing required key(s) mass" in err


def test_several_speeds_and_forces_run_as_one_batch(capsys):
    """``--speed A,B --static-force C,D`` runs the grid through the batch engine: one JSON object
    whose ``runs`` hold one entry per (speed, force), speed-major, each with the single-run keys and
    the statistics of simulate_many for the same points and numerics (the same engine: exact), and
    the warning that 0.5 m elements under-resolve 160 and 180 km/h."""
    from presag_opt.dynamics.batch import simulate_many
    from presag_opt.dynamics.settings import OperatingPoint

    code, out, err = _run(capsys, "--case", "case_study_st98", "--speed", "160,180", "--static-force", "70,120",
                          "--time-step", "2", "--element-length", "0.5", "--json")
    assert code == 0
    printed = json.loads(out)
    assert [(r["speed_kmh"], r["static_force_N"]) for r in printed["runs"]] == [
        (160.0, 70.0), (160.0, 120.0), (180.0, 70.0), (180.0, 120.0)]
    for run in printed["runs"]:
        assert set(REQUIRED_KEYS) | {"analysed_spans", "time_step_ms", "wall_time_s"} <= set(run)
    case = load_case("case_study_st98")
    from presag_opt.static.form_finding import form_find

    state = form_find(case.catenary, case.settings.static)
    api = simulate_many(state, case.pantograph, [OperatingPoint(
        speed=180 / 3.6, static_force=70.0, aero_coefficient=case.operation.aero_coefficient)],
        settings=case.settings.with_fixed_numerics()).runs[0]
    assert printed["runs"][2]["sigma_N"] == api.statistics[0].std_force
    assert printed["runs"][2]["warnings"] == list(api.warnings)
    assert "presag: warning: element_length = 0.5 m under-resolves 180 km/h" in err
    assert printed["runs"][2]["uplift_max_mm"] == pytest.approx(api.uplift_max * 1e3, rel=1e-15)


def test_an_empty_list_of_forces_is_one_line(capsys):
    assert main(["simulate", "--case", "case_study_st98", "--speed", "90", "--static-force", ","]) == 2
    assert "argument --static-force: ',': give at least one value" in capsys.readouterr().err
