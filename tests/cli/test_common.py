"""``presag_opt.cli.common``: running a handler (exit codes, one-line errors, warnings once), the
argument types of the shared grammar (bands ``LOW:HIGH``, lists ``A,B,C``), the output checks made
before any work, tables, JSON and the progress display. All in-process: each test takes milliseconds."""

from __future__ import annotations

import argparse
import errno
import json
import math
import sys
import threading
import warnings
from pathlib import Path

import numpy as np
import pytest

from presag_opt.cli import common
from presag_opt.cli.common import Progress, output_folder, progress
from presag_opt.dynamics import cost
from presag_opt.errors import ConvergenceError, ModelError, StorageError


def test_progress_shows_only_after_its_delay_and_on_a_terminal(capsys, monkeypatch):
    with Progress(True, delay=3600.0) as later:
        later("form-finding")
    assert capsys.readouterr().err == ""
    with Progress(True, delay=0.0) as shown:
        shown("form-finding")
    assert "form-finding" in capsys.readouterr().err
    options = argparse.Namespace(quiet=False, progress=False)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False)
    with progress(options) as piped:
        piped("form-finding")
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    with progress(argparse.Namespace(quiet=True, progress=False)) as quiet:
        quiet("form-finding")
    assert capsys.readouterr().err == ""


def test_a_shown_progress_display_redraws_itself_between_messages(monkeypatch):
    """A long step (the first four units of a sweep) must not leave the display blank: once shown, the
    display is redrawn with its last message and elapsed time without a new message."""
    drawn = threading.Event()

    class Terminal:
        def __init__(self):
            self.text = []

        def write(self, text):
            self.text.append(text)
            if sum("first unit" in t for t in self.text) >= 3:  # the call draws it once; the rest is the ticker
                drawn.set()
            return len(text)

        def flush(self):
            pass

    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    monkeypatch.setattr(common, "PROGRESS_TICK", 0.01)
    with Progress(True, delay=0.0) as shown:
        shown("first unit")
        assert drawn.wait(timeout=60)
    assert shown._ticker is not None and not shown._ticker.is_alive()  # closed with the display


def test_an_unexpected_error_is_one_line_without_a_traceback(capsys, monkeypatch):
    def handler(args):
        raise RuntimeError("index 7 is out of bounds\nsecond line")

    monkeypatch.delenv("PRESAG_DEBUG", raising=False)
    status = common.run(handler, argparse.Namespace(no_cache=True))
    err = capsys.readouterr().err
    assert status == common.EXIT_INTERNAL
    assert err.startswith("presag: internal error: RuntimeError: index 7 is out of bounds in test_common.py:")
    assert len(err.strip().splitlines()) == 1 and "PRESAG_DEBUG=1 shows the traceback" in err



def test_a_raw_os_error_is_one_line(capsys):
    def handler(args):
        raise PermissionError(13, "Permission denied", "/somewhere/file.png")

    assert common.run(handler, argparse.Namespace(no_cache=True)) == common.EXIT_STORAGE
    assert capsys.readouterr().err == ("presag: error: /somewhere/file.png: Permission denied "
                                       "(check the permissions)\n")


@pytest.mark.parametrize(("name", "words"), [("file.txt", "--out file.txt: is a file"),
                                             ("missing/report", "the folder missing does not exist")])
def test_output_folder_is_checked_before_any_work(tmp_path, monkeypatch, name, words):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "file.txt").write_text("x")
    with pytest.raises(ModelError, match=words):
        output_folder(name)
    assert output_folder("new") == Path("new") and (tmp_path / "new").is_dir()


def _handler_raising(exc: BaseException):
    def handler(args):
        raise exc

    return handler


@pytest.mark.parametrize(("exc", "status", "line"), [
    (ModelError("span = 7 is outside the valid range [0, 4]"), common.EXIT_BAD_INPUT,
     "presag: error: span = 7 is outside the valid range [0, 4]\n"),
    (ConvergenceError("IPOPT stopped: Maximum_Iterations_Exceeded", {"iter_count": 3000}), common.EXIT_NOT_CONVERGED,
     "presag: error: IPOPT stopped: Maximum_Iterations_Exceeded\n"),
    (StorageError("/x/s.nc: no space left on the device; free some space", errno.ENOSPC, "/x/s.nc"),
     common.EXIT_STORAGE, "presag: error: /x/s.nc: no space left on the device; free some space\n"),
    (KeyboardInterrupt(), common.EXIT_INTERRUPTED, "presag: interrupted\n"),
])
def test_each_expected_error_is_one_line_with_its_own_exit_status(capsys, exc, status, line):
    """The exit statuses are the documented ones (2 bad input, 3 not converged, 4 storage, 130 Ctrl-C)."""
    assert common.run(_handler_raising(exc), argparse.Namespace(no_cache=True)) == status
    captured = capsys.readouterr()
    assert captured.err == line and captured.out == ""
    assert (common.EXIT_BAD_INPUT, common.EXIT_NOT_CONVERGED, common.EXIT_STORAGE, common.EXIT_INTERRUPTED) == (
        2, 3, 4, 130)


def test_a_handler_returning_none_exits_zero_and_its_own_status_is_kept():
    assert common.run(lambda args: None, argparse.Namespace(no_cache=True)) == 0
    assert common.run(lambda args: 5, argparse.Namespace(no_cache=True)) == 5


@pytest.mark.parametrize(("code", "hint"), [(errno.ENOSPC, " (free some space)"), (errno.EACCES, " (check the permissions)"),
                                            (errno.EROFS, " (the file system is read-only)"), (errno.ENOENT, "")])
def test_os_error_line_names_the_file_the_reason_and_what_to_do(code, hint):
    exc = OSError(code, "the reason", "/data/a.nc")
    assert common.os_error_line(exc) == f"/data/a.nc: the reason{hint}"
    assert common.os_error_line(OSError(code, "the reason")) == f"the reason{hint}"  # no file: no "None: "


def test_a_warning_raised_twice_is_shown_once_and_listed_in_the_json(capsys):
    def handler(args):
        for _ in range(3):
            warnings.warn("speed ratio β = 0.75 exceeds 0.7", UserWarning, stacklevel=1)
        common.print_warnings(["speed ratio   β = 0.75\nexceeds 0.7", "second"])  # the same text once spaces fold
        common.print_json({"value": 1.0, "warnings": ["own"]})

    assert common.run(handler, argparse.Namespace(no_cache=True)) == 0
    captured = capsys.readouterr()
    assert captured.err.splitlines() == ["presag: warning: speed ratio β = 0.75 exceeds 0.7", "presag: warning: second"]
    assert json.loads(captured.out)["warnings"] == ["own", "speed ratio β = 0.75 exceeds 0.7", "second"]
    common.run(lambda args: None, argparse.Namespace(no_cache=True))
    assert common.shown_warnings() == []  # each command starts with none shown


def test_json_converts_numpy_and_writes_non_finite_numbers_as_null(capsys):
    common.print_json([np.float64(1.5), np.int64(3), np.bool_(True), np.array([[1.0, np.nan], [np.inf, -2.0]]),
                       {1: math.nan}, (np.float32(0.25),)])
    assert json.loads(capsys.readouterr().out) == [1.5, 3, True, [[1.0, None], [None, -2.0]], {"1": None}, [0.25]]


def test_table_right_aligns_each_column_to_its_widest_cell_and_shows_none_as_a_dash():
    text = common.table(["span", "S [mm]"], [[1, 54.0], [12, None]], ["{}", "{:.1f}"])
    assert text.splitlines() == ["span  S [mm]", "----  ------", "   1    54.0", "  12       -"]
    assert common.table(["a"], []).splitlines() == ["a", "-"]


@pytest.mark.parametrize(("text", "expected"), [("70:148", (70.0, 148.0)), ("140", (140.0, 140.0)),
                                                ("-5:1e2", (-5.0, 100.0))])
def test_a_band_is_low_colon_high_and_one_value_is_both_ends(text, expected):
    assert common.band(text) == expected


@pytest.mark.parametrize(("parse", "text", "words"), [
    (common.band, "70,148", "a band is written LOW:HIGH (e.g. 70:148); A,B,C is the list syntax"),
    (common.band, "1:2:3", "'1:2:3': a band is written LOW:HIGH"),
    (common.band, "70:x", "'x' is not a number"),
    (common.float_list, "50:150", "this option takes a list of values A,B,C"),
    (common.float_list, ",", "give at least one value"),
    (common.positive_float, "nan", "'nan' is not a finite number"),
    (common.positive_float, "inf", "'inf' is not a finite number"),
    (common.positive_float, "ten", "'ten' is not a number"),
])
def test_the_grammar_refuses_the_other_syntax_with_a_hint(parse, text, words):
    with pytest.raises(argparse.ArgumentTypeError) as caught:
        parse(text)
    assert words in str(caught.value)


def test_a_list_is_comma_separated_and_one_value_is_a_list_of_one():
    assert common.float_list("50,100, 150,") == [50.0, 100.0, 150.0]
    assert common.float_list("90") == [90.0]


def test_output_folder_is_created_and_refuses_files_and_missing_parents(tmp_path):
    assert common.output_folder(str(tmp_path / "figs"), option="--plot") == tmp_path / "figs"
    assert (tmp_path / "figs").is_dir() and not list((tmp_path / "figs").iterdir())  # the probe leaves nothing
    (tmp_path / "file").write_text("x")
    with pytest.raises(ModelError, match=r"--plot .*file: is a file; give a folder"):
        common.output_folder(str(tmp_path / "file"), option="--plot")
    with pytest.raises(ModelError, match=r"--out .*: the folder .*missing does not exist"):
        common.output_folder(str(tmp_path / "missing" / "out"))


def test_progress_needs_at_most_one_of_quiet_and_progress(monkeypatch):
    with pytest.raises(ModelError, match="give at most one of --quiet and --progress"):
        common.progress_enabled(argparse.Namespace(quiet=True, progress=True))
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False)
    assert common.progress_enabled(argparse.Namespace(quiet=False, progress=True)) is True
    assert common.progress_enabled(argparse.Namespace()) is False


@pytest.mark.parametrize(("seconds", "quiet", "line"), [
    (11.0, False, "presag: form-finding 5000 nodes takes about 11 s on a typical machine (Ctrl-C stops it)\n"),
    (600.0, False, "presag: form-finding 5000 nodes takes about 10 min on a typical machine (Ctrl-C stops it)\n"),
    (9000.0, False, "presag: form-finding 5000 nodes takes about 2.5 h on a typical machine (Ctrl-C stops it)\n"),
    (cost.LONG_FORM_FINDING, False, ""), (600.0, True, ""),
])
def test_a_long_form_finding_is_announced_unless_quiet(capsys, seconds, quiet, line):
    common.announce_form_finding(argparse.Namespace(quiet=quiet), 5000, seconds)
    assert capsys.readouterr().err == line


def test_long_work_is_announced_with_its_description_above_two_minutes(capsys):
    class Estimate:
        def __init__(self, seconds):
            self.seconds = seconds

        def describe(self):
            return "3 runs on 1 000 nodes: about 4 min"

    common.announce_work(argparse.Namespace(), Estimate(cost.LONG_WORK + 1.0))
    assert capsys.readouterr().err == "presag: 3 runs on 1 000 nodes: about 4 min (Ctrl-C stops it)\n"
    common.announce_work(argparse.Namespace(), Estimate(cost.LONG_WORK))
    common.announce_work(argparse.Namespace(quiet=True), Estimate(1e6))
    assert capsys.readouterr().err == ""


def test_model_help_lists_the_built_in_models():
    from presag_opt.system.loader import builtin_model_names

    text = common.model_help("catenaries", default="st_9.8_ideal")
    assert text == f"model file or built-in name ({', '.join(builtin_model_names('catenaries'))}); default st_9.8_ideal"
    assert "st_9.8_ideal" in builtin_model_names("catenaries")
