"""Runs the bad-input catalogue (tests/catalogue.py): every case ends in its documented error or result."""

import warnings
from pathlib import Path

import pytest

import synergrasp as sg
from synergrasp.cli import main

from .catalogue import CASES, cli_files

PACKAGE = Path(sg.__file__).resolve().parent


def raised_in_synergrasp(exc):
    """The innermost frame of the exception's traceback is synergrasp's own code."""
    tb = exc.__traceback__
    while tb.tb_next is not None:
        tb = tb.tb_next
    return PACKAGE in Path(tb.tb_frame.f_code.co_filename).resolve().parents


@pytest.mark.parametrize("case", CASES, ids=[case.id for case in CASES])
def test_case(case, tmp_path, capsys):
    if case.argv is not None:
        cli_files(tmp_path)
        argv = [a.replace("{tmp}", str(tmp_path)) for a in case.argv]
        try:
            code = main(argv + (["--out", str(tmp_path / "out"), "--quiet"] if argv[:1] == ["plan"] and "--out" not in argv else []))
        except SystemExit as exit:
            code = exit.code
        err = capsys.readouterr().err
        assert code == 2, f"exit status {code}, stderr: {err}"
        assert case.says in err and "Traceback" not in err, err
        return
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if case.raises is None:
            result = case.call(tmp_path)
            assert case.check(result), f"unexpected result {result!r}"
            return
        with pytest.raises(Exception) as info:
            case.call(tmp_path)
    exc = info.value
    assert isinstance(exc, case.raises), f"{type(exc).__name__}: {exc}"
    assert case.says in str(exc), str(exc)
    assert raised_in_synergrasp(exc), f"raised from inside a dependency: {type(exc).__name__}: {exc}"


def test_the_catalogue_is_large_and_covers_the_command_line():
    assert len(CASES) >= 60
    assert len({case.id for case in CASES}) == len(CASES), "case names must be unique"
    assert {case.entry for case in CASES if case.argv is not None} >= {"synergrasp plan", "synergrasp demo"}
