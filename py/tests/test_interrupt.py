"""Long jobs: the GIL is released, progress is reported, Ctrl-C stops them within a second."""

import _thread
import signal
import threading
import time

import pytest

import sceneinfo

BIG_JOB = 2_000_000_000  # far more lines than any test lets run


def test_keyboard_interrupt_stops_a_long_measure():
    scene = sceneinfo.Scene.preset("cube", grid=6)
    start = time.monotonic()

    def guard(done, total):
        # Bounds the test: a job Ctrl-C failed to stop fails here instead of running for hours
        if time.monotonic() - start > 60:
            # Says whether the interrupt was sent and lost, or never sent (the timer starved)
            raise AssertionError(
                "KeyboardInterrupt did not stop the job "
                f"(the timer fired: {timer.finished.is_set()}; {done:,} of {total:,} lines)"
            )

    # A shell that starts the tests in the background without job control (`./scripts/test.sh
    # &` in a script, nohup) makes them ignore SIGINT, and then Python installs no handler and
    # `interrupt_main` does nothing: install Python's own handler for this test
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.5, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sceneinfo.measure(scene, lines=BIG_JOB, threads=2, progress=guard)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)


def test_the_gil_is_released_while_lines_are_cast():
    scene = sceneinfo.Scene.preset("cube", grid=6)
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.005)

    t = threading.Thread(target=count)
    t.start()
    try:
        sceneinfo.measure(scene, lines=600_000, threads=1)
    finally:
        stop.set()
        t.join()
    # The other Python thread ran while the job did
    assert len(ticks) > 3


def test_progress_is_reported_and_its_error_stops_the_job():
    scene = sceneinfo.Scene.preset("cube", grid=6)
    seen = []
    sceneinfo.measure(scene, lines=600_000, threads=2, progress=lambda d, t: seen.append((d, t)))
    assert seen and seen[-1] == (600_000, 600_000)
    assert all(d <= t for d, t in seen)

    class Stop(Exception):
        pass

    def fail(done, total):
        raise Stop()

    with pytest.raises(Stop):
        sceneinfo.measure(scene, lines=BIG_JOB, threads=2, progress=fail)
