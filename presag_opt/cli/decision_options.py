"""The options every command that answers "which pre-sag?" shares, and how they reach the pipeline.

One grammar for the band and the decision, whichever command asks:

- the band: ``--static-force LOW:HIGH`` (N), ``--min-speed``/``--max-speed`` (km/h), ``--aero``
  (N/(km/h)²), ``--allow-supercritical`` (:func:`add_band_options`, :func:`operating_band`);
- the decision: ``--within PERCENT`` (10 or 10 %), ``--uplift-limit MM``, ``--crew-tolerance MM`` or
  ``--dropper-error MM`` (the crew tolerance from a Monte Carlo of per-dropper errors), ``--study
  STORE`` (a stored validity study), ``--dynamic-robust`` (:func:`add_decision_options`);
- the numerics: ``--element-length M`` and ``--workers N`` from :func:`add_numerics_options` and
  :func:`add_workers_option`, one default each.

The decision is printed by :func:`print_decision` (its lines, the same for every command) and
:func:`decision_json` (its JSON); the option of the running command that would supply each missing
kind of evidence comes from the command's own map.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Mapping

from presag_opt.cli.common import band, positive_float
from presag_opt.design.band import CASE_STUDY_BAND, OperatingBand
from presag_opt.design.evidence import CREW_TOLERANCE
from presag_opt.errors import ModelError
from presag_opt.jobs import band as band_job
from presag_opt.jobs.options import ELEMENT_LENGTH, UPLIFT_LIMIT_MM, WITHIN_PERCENT, WORKERS
from presag_opt.units import KMH

CASE_STATIC_FORCE = (CASE_STUDY_BAND.static_force_low, CASE_STUDY_BAND.static_force_high)
CASE_SPEED = CASE_STUDY_BAND.speed_kmh
CASE_AERO = CASE_STUDY_BAND.aero_coefficient_kmh
"""The case study's band in the command line's units: F_stat [N], speeds [km/h], α_ae [N/(km/h)²]."""

AERO_METAVAR = "N/(KMH)^2"
"""The one spelling of the aerodynamic coefficient's unit in the command line."""


def add_band_options(parser: argparse.ArgumentParser) -> None:
    """``--static-force``, ``--min-speed``, ``--max-speed``, ``--aero`` and ``--allow-supercritical``: the
    operating band, by default the case study's (read back with :func:`operating_band`)."""
    g = parser.add_argument_group("operating band (default: the case study)")
    g.add_argument("--static-force", metavar="N:N", type=band, default=CASE_STATIC_FORCE,
                   help="static contact force band LOW:HIGH in N, or one value (default %g:%g)" % CASE_STATIC_FORCE)
    g.add_argument("--min-speed", metavar="KMH", type=positive_float, default=CASE_SPEED[0],
                   help=f"lowest speed in km/h (default {CASE_SPEED[0]:g})")
    g.add_argument("--max-speed", metavar="KMH", type=positive_float, default=CASE_SPEED[1],
                   help=f"highest speed in km/h (default {CASE_SPEED[1]:g})")
    g.add_argument("--aero", metavar=AERO_METAVAR, type=positive_float, default=CASE_AERO,
                   help=f"aerodynamic uplift coefficient α_ae in N/(km/h)² (default {CASE_AERO:g})")
    g.add_argument("--allow-supercritical", action="store_true",
                   help="accept a --max-speed at or above β = 0.7 of a model's contact-wire wave speed "
                        "(EN 50119's limit)")


def operating_band(args: argparse.Namespace) -> OperatingBand:
    """The band from the command-line options (validated by :class:`~presag_opt.design.band.OperatingBand`)."""
    return OperatingBand.from_kmh(static_force=args.static_force, speed_kmh=(args.min_speed, args.max_speed),
                                  aero_coefficient_kmh=args.aero)


def check_band_speed(args: argparse.Namespace, models: list) -> None:
    """Refuse a band whose ``--max-speed`` is at or above β = 0.7 on any of the models (catenaries or
    names of model files), before any work, unless ``--allow-supercritical`` accepts it.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed options of a command with :func:`add_band_options`.
    models : list of Catenary or str
        The catenaries the band is designed on, or their model names or paths.
    """
    band_job.check_band_speed(operating_band(args), models, args.allow_supercritical, accept="--allow-supercritical")


def within_percent(text: str) -> float:
    """``10`` or ``10%`` -> 10 (percent); the range is the API's to check."""
    try:
        return float(str(text).strip().removesuffix("%").strip())
    except ValueError:
        raise ModelError(f"--within = {text!r}: write a percentage such as 10 (or 10%)") from None


def add_decision_options(parser: argparse.ArgumentParser, *, simulated: str, dynamic_robust: bool = True,
                         monte_carlo: bool = True) -> None:
    """The options of the decision (see the module docstring).

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The sub-command's parser.
    simulated : str
        What ``--dynamic-robust`` simulates, for its help.
    dynamic_robust : bool
        Offer ``--dynamic-robust`` (``presag robust`` has ``--dynamic`` instead).
    monte_carlo : bool
        Offer ``--dropper-error``.
    """
    g = parser.add_argument_group("decision")
    g.add_argument("--within", default=f"{WITHIN_PERCENT:g}", metavar="PERCENT",
                   help=f"allowed loss of the tolerance intervals in %%, e.g. 10 or 10%% (default {WITHIN_PERCENT:g})")
    g.add_argument("--uplift-limit", metavar="MM", type=positive_float, default=UPLIFT_LIMIT_MM,
                   help=f"steady-arm uplift limit in mm (default {UPLIFT_LIMIT_MM:g}, the case study's "
                        "arms without uplift stop)")
    g.add_argument("--crew-tolerance", metavar="MM", type=positive_float, default=None,
                   help=f"the crew's build tolerance of the mid-span pre-sag, ± in mm (default {CREW_TOLERANCE * 1e3:g}, "
                        "assumed: half of a 5 mm cutting step); the pre-sag is built with at least this margin inside "
                        "the tolerance intervals")
    if monte_carlo:
        g.add_argument("--dropper-error", metavar="MM", type=positive_float, default=None,
                       help="instead of --crew-tolerance: σ of each dropper's cut length in mm; the crew tolerance is "
                            "then the P95 of the mid-span pre-sag error of 10 000 Monte Carlo builds")
    g.add_argument("--study", metavar="STORE", default=None,
                   help="a validity study written by `presag sweep`: its β* and its dynamic uplift enter the decision")
    if dynamic_robust:
        g.add_argument("--dynamic-robust", action="store_true",
                       help=f"also run the dynamic robust design of the band on {simulated} and decide with it (the "
                            "decision is then final); about half a minute for the case study on an idle 2-core machine")


def add_numerics_options(parser: argparse.ArgumentParser) -> None:
    """``--element-length`` and ``--workers``, with the one default each."""
    add_element_length_option(parser)
    add_workers_option(parser)


def add_element_length_option(parser: argparse.ArgumentParser) -> None:
    """``--element-length M``, the one option for the static model's longest element."""
    parser.add_argument("--element-length", metavar="M", type=positive_float, default=ELEMENT_LENGTH,
                        help=f"longest element of the static model in m (default {ELEMENT_LENGTH:g}; valid 0.01–5, "
                             "small values take long)")


def add_workers_option(parser: argparse.ArgumentParser, *, scheduler: bool = False) -> None:
    """``--workers N``, the one option for local worker processes (read back with :func:`workers_of`).

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The sub-command's parser.
    scheduler : bool
        The command also takes ``--scheduler`` (a Dask cluster instead of local workers).
    """
    parser.add_argument("--workers", metavar="N", type=int, default=None,
                        help=f"local worker processes (default: the CPU count, {WORKERS} here"
                        + ("; not with --scheduler)" if scheduler else ")"))


def workers_of(args: argparse.Namespace) -> int:
    """The local worker processes of a command: ``--workers`` or the default :data:`WORKERS`.

    Raises
    ------
    ModelError
        ``--workers`` with ``--scheduler``, or a count outside [1, 64].
    """
    given = getattr(args, "workers", None)
    if given is not None and getattr(args, "scheduler", None) is not None:
        raise ModelError("give either --workers or --scheduler, not both")
    workers = WORKERS if given is None else given
    if not 1 <= workers <= 64:
        raise ModelError(f"--workers = {workers} is outside the valid range [1, 64]")
    return workers


def decision_keywords(args: argparse.Namespace) -> dict:
    """The jobs' keyword arguments of the decision from its options (mm, %; :mod:`presag_opt.jobs`)."""
    crew = getattr(args, "crew_tolerance", None)
    error = getattr(args, "dropper_error", None)
    if crew is not None and error is not None:
        raise ModelError("give --crew-tolerance or --dropper-error, not both")
    return {"within_percent": within_percent(args.within), "uplift_limit_mm": args.uplift_limit,
            "crew_tolerance_mm": crew, "dropper_error_mm": error, "study": args.study}


def decision_settings(args: argparse.Namespace) -> dict:
    """The pipeline's keyword arguments from the decision options (lengths in m, shares)."""
    return band_job.decision_settings(**decision_keywords(args))


def announce_dynamic(args: argparse.Namespace, catenary, band, pantograph, where: str) -> None:
    """Say on standard error what the dynamic robust design will cost, before it runs.

    Parameters
    ----------
    args : argparse.Namespace
        The command's options (``--quiet``).
    catenary : Catenary
        The system simulated.
    band : OperatingBand
        The band. [N], [m/s]
    pantograph : Pantograph
        The pantograph.
    where : str
        What is simulated, named in the announcement.
    """
    from presag_opt.robust.dynamic_study import dynamic_cost, simulated_band

    if getattr(args, "quiet", False):
        return
    simulated = simulated_band(band)
    cost = dynamic_cost(catenary, pantograph, simulated, workers=workers_of(args))
    print(f"presag: the dynamic robust design of {where} at {simulated.speed_low / KMH:.0f}–"
          f"{simulated.speed_high / KMH:.0f} km/h: {cost.describe()}, after its quasi-static robust design",
          file=sys.stderr, flush=True)


def print_decision(lines: list[str]) -> None:
    """Print a decision's lines (:meth:`~presag_opt.design.decision.Decision.lines`) and a blank line."""
    print("\n".join(lines) + "\n")


def decision_json(decision, options: Mapping[str, str], span_lengths=None) -> dict:
    """The decision's JSON with what was not checked named by the running command's options.

    Parameters
    ----------
    decision : Decision
        The decision.
    options : mapping of str to str
        Evidence name to this command's option that supplies it.
    span_lengths : sequence of float, optional
        A line's span lengths (the headline is then S_rel × span length). [m]
    """
    out = decision.to_dict(span_lengths)
    out["not_checked_text"] = decision.not_checked(options)
    return out
