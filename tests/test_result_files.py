"""Result files explain themselves (issue 23): every unit string parses with udunits (cf-units, the
CF conventions' unit library) with its meaning kept, and commit, date and scenario are stated;
progress reaches the terminal as well as the log."""

import ast
from pathlib import Path

import cf_units
import numpy as np
import pytest
import xarray as xr

from rail.setup import io

ROOT = Path(__file__).resolve().parents[1]


def _unit_literals():
    """The units argument of every data_var(...) call (rail.setup.io.data_var) in rail/ and the
    workflow's scripts that is a plain string."""
    found = set()
    for path in [*(ROOT / "rail").rglob("*.py"), *(ROOT / "workflow/scripts").glob("*.py")]:
        for node in ast.walk(ast.parse(path.read_text())):
            f = node.func if isinstance(node, ast.Call) else None
            if f is not None and (getattr(f, "id", None) or getattr(f, "attr", None)) == "data_var" and len(node.args) >= 3:
                arg = node.args[2]
                if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
                    found.add(arg.value)
    return sorted(found)


def test_the_source_has_unit_strings_to_check():
    units = _unit_literals()
    assert len(units) > 15 and "dB re 1 um" in units and "um per 100000 axle passages" in units


@pytest.mark.parametrize("units", _unit_literals())
def test_every_unit_string_parses_with_udunits_after_finalize(units):
    converted, extra = io.cf_units(units)
    cf_units.Unit(converted)  # raises ValueError for a string udunits cannot parse
    if converted != units:
        assert extra["units_text"] == units


def test_levels_and_rates_keep_their_meaning():
    assert io.cf_units("dB re 1 um") == ("1", {"level_unit": "dB", "units_text": "dB re 1 um", "level_reference": "1 um rms"})
    u, extra = io.cf_units("um per 100000 passages")
    assert extra["per"] == "passage"
    # 3 um per 100,000 passages is 3e-5 um per passage = 3e-11 m
    assert cf_units.Unit(u).convert(3.0, cf_units.Unit("m")) == pytest.approx(3e-11)
    assert cf_units.Unit(io.cf_units("1 per 100000 passages")[0]).convert(2.0, cf_units.Unit("1")) == pytest.approx(2e-5)
    assert io.cf_units("m/s") == ("m/s", {})
    assert io.cf_units(io.cf_units("m per 10000 passages")[0])[0] == "0.0001 m"  # idempotent


def test_finalize_states_commit_date_and_scenario():
    ds = xr.Dataset({"a": ("x", np.arange(3.0), {"units": "dB re 1 um", "long_name": "a level"}),
                     "b": ("update", np.arange(2.0), {"units": "1", "long_name": "per update"})},
                    coords={"x": ("x", np.arange(3.0), {"units": "m", "long_name": "position"})})
    out = io.finalize(ds, {"a": 1}, title="t", source="s", scenario="soft_pad")
    assert out.attrs["scenario"] == "soft_pad"
    assert out.attrs["code_version"].split()[0] and "date_created" in out.attrs
    assert out["a"].attrs["units"] == "1" and out["a"].attrs["level_unit"] == "dB"
    assert "update" in out.coords and out["update"].attrs["units"] == "1"  # a coordinate on every dimension
    assert out["x"].attrs["axis"] == "X"


def test_progress_goes_to_the_log_whole_and_to_the_terminal_as_a_bar():
    import io as _io

    from rail.setup.progress import Tee

    log, term = _io.StringIO(), _io.StringIO()
    t = Tee(log, "growth default V40", terminal=term)
    print("resuming from x.npz: 10000 of 20000 passages done", file=t, flush=True)
    print("10000 of 20000 passages, 825 passages/s, 12 s left", file=t, flush=True)
    t.write("20000 of 20000 ")
    t.write("passages, 830 passages/s, 0 s left\n")
    assert log.getvalue() == ("resuming from x.npz: 10000 of 20000 passages done\n"
                              "10000 of 20000 passages, 825 passages/s, 12 s left\n"
                              "20000 of 20000 passages, 830 passages/s, 0 s left\n")
    shown = term.getvalue()
    assert "[growth default V40] resuming from x.npz" in shown
    assert "growth default V40" in shown and "20000/20000" in shown  # the tqdm bar, completed


def test_time_left_is_extrapolated_from_the_fraction_done():
    from rail.setup.progress import duration, time_left

    assert time_left(1, 4, 30.0) == 90.0  # a quarter in 30 s: three quarters left take 90 s
    assert time_left(4, 4, 120.0) == 0.0
    assert time_left(0, 4, 5.0) is None and time_left(0, 0, 5.0) is None  # nothing to extrapolate from
    assert [duration(s) for s in (0.4, 45, 119, 120, 1800, 7199, 7200, 9000)] == [
        "0 s", "45 s", "119 s", "2 min", "30 min", "120 min", "2.0 h", "2.5 h"]


def test_spectrum_progress_lines_say_the_time_used_and_left_on_a_fake_clock():
    # issue 45: a spectrum's log gave the time used but no time left
    import io as _io

    from rail.setup.progress import progress_lines

    ticks = iter([0.0, 60.0, 120.0, 125.0, 300.0, 600.0])  # made at 0; the lines at 60, 120, ... s
    log = _io.StringIO()
    cb = progress_lines(log, clock=lambda: next(ticks))
    cb("1 of 4 probe batches (grid phase 1 of 1, 10 lines)")
    cb("2 of 4 probe batches (grid phase 1 of 1, 10 lines)")
    cb("linearity check: 2 nm against 1 nm")
    cb("3 of 4 probe batches (grid phase 1 of 1, 10 lines)")
    cb("4 of 4 probe batches (grid phase 1 of 1, 10 lines)")
    assert log.getvalue().splitlines() == [
        "1 of 4 probe batches (grid phase 1 of 1, 10 lines), 60 s elapsed, about 3 min left",  # 60 s x 3
        "2 of 4 probe batches (grid phase 1 of 1, 10 lines), 2 min elapsed, about 2 min left",
        "linearity check: 2 nm against 1 nm, 2 min elapsed",
        "3 of 4 probe batches (grid phase 1 of 1, 10 lines), 5 min elapsed, about 100 s left",
        "4 of 4 probe batches (grid phase 1 of 1, 10 lines), 10 min elapsed, about 0 s left"]


def test_a_count_within_a_count_is_timed_on_its_own():
    # a table job counts node blocks within each table and the tables: each estimate from its own clock
    import io as _io

    from rail.setup.progress import progress_lines

    ticks = iter([0.0, 0.0, 10.0, 20.0, 20.0, 30.0, 40.0, 50.0])
    log = _io.StringIO()
    cb = progress_lines(log, "receptance V40: ", clock=lambda: next(ticks))
    for text in ("0 of 2 node blocks", "1 of 2 node blocks", "2 of 2 node blocks", "1 of 2 tables",
                 "0 of 2 node blocks", "1 of 2 node blocks", "2 of 2 tables"):
        cb(text)
    lines = log.getvalue().splitlines()
    assert lines[0] == "0 of 2 node blocks, 0 s elapsed [receptance V40]"  # no estimate from nothing
    assert lines[1] == "1 of 2 node blocks, 10 s elapsed, about 10 s left [receptance V40]"
    assert lines[3] == "1 of 2 tables, 20 s elapsed, about 20 s left [receptance V40]"  # from the start, not the last block
    assert lines[5] == "1 of 2 node blocks, 40 s elapsed, about 10 s left [receptance V40]"  # the second table's blocks from their 0
    assert lines[6] == "2 of 2 tables, 50 s elapsed, about 0 s left [receptance V40]"
