"""gbh_drake.interrupts in this process (real signals sent to ourselves): a signal during an
import waits for the import to end, a dropped interrupt is raised again at a checkpoint and still
decides the exit code, a deferred block is not cut short, a nohup'ed SIGHUP stays ignored."""

from __future__ import annotations

import os
import signal
import sys
import time

import pytest

from gbh_drake import interrupts


@pytest.fixture
def handled():
    with interrupts.handled():
        yield


def _module(tmp_path, name: str, body: str):
    (tmp_path / f"{name}.py").write_text(body)
    sys.path.insert(0, str(tmp_path))
    return name


def test_a_signal_inside_an_import_waits_for_the_import_to_end(tmp_path, handled):
    """The import runs to its end (no 'ImportError: initialization failed', no guard in it
    catching the interrupt); KeyboardInterrupt comes right after."""
    name = _module(tmp_path, "gbh_slow_import", (
        "import os, signal, time\n"
        "os.kill(os.getpid(), signal.SIGINT)\n"
        "try:\n"
        "    time.sleep(0.3)\n"
        "except BaseException:\n"  # trimesh's guards: an interrupt raised here would be lost
        "    raise SystemExit('interrupted inside the import')\n"
        "FINISHED = True\n"))
    try:
        with pytest.raises(KeyboardInterrupt):
            __import__(name)
            time.sleep(1.0)  # the exception comes within RETRY s of the import's end
        assert sys.modules[name].FINISHED
    finally:
        sys.path.remove(str(tmp_path))
        sys.modules.pop(name, None)
    assert interrupts.received() == signal.SIGINT and interrupts.exit_code() == 130


@pytest.mark.parametrize(("signum", "exception", "code"), [
    (signal.SIGINT, KeyboardInterrupt, 130),
    (signal.SIGTERM, interrupts.Terminated, 143),
    (signal.SIGHUP, interrupts.HungUp, 129),
])
def test_a_dropped_interrupt_is_raised_again_and_decides_the_code(signum, exception, code,
                                                                   handled):
    try:
        os.kill(os.getpid(), signum)
        time.sleep(1.0)
    except BaseException:  # a careless library drops it
        pass
    assert interrupts.received() == signum and interrupts.exit_code() == code
    with pytest.raises(exception):
        interrupts.check()  # the next checkpoint (a simulator step, the commit, a row)
    assert interrupts.describe() == interrupts.SIGNALS[signum]


def test_the_second_signal_gets_the_default_action(handled):
    with pytest.raises(interrupts.Terminated):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(1.0)
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL
    assert signal.getsignal(signal.SIGINT) is signal.SIG_DFL


def test_a_deferred_block_is_not_cut_short(handled):
    done = []
    with pytest.raises(KeyboardInterrupt), interrupts.deferred():
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(0.2)
        done.append("the row and its replay")
    assert done == ["the row and its replay"]


def test_handlers_are_put_back():
    before = {s: signal.getsignal(s) for s in interrupts.SIGNALS}
    with interrupts.handled():
        assert signal.getsignal(signal.SIGTERM) is not before[signal.SIGTERM]
    assert {s: signal.getsignal(s) for s in interrupts.SIGNALS} == before
    with interrupts.handled():
        assert interrupts.received() is None


def test_an_ignored_sighup_stays_ignored():
    """``nohup gbh run ...``: the hang-up is not turned into an exit."""
    previous = signal.signal(signal.SIGHUP, signal.SIG_IGN)
    try:
        with interrupts.handled():
            assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
            os.kill(os.getpid(), signal.SIGHUP)
            time.sleep(0.1)
            assert interrupts.received() is None
    finally:
        signal.signal(signal.SIGHUP, previous)


def test_without_a_signal_the_checkpoints_pass(handled):
    interrupts.check()
    with interrupts.deferred():
        pass
    assert interrupts.exit_code() == 130  # a KeyboardInterrupt raised by hand (tests)
