"""Long calls run without the GIL, report progress, and stop on Ctrl-C or a raising callback."""
import os
import signal
import subprocess
import sys
import threading

import pytest

import microbrdf as mb

SCENE_NAME = "lambert_plane.json"


def test_raising_progress_callback_stops_the_call(data):
    scene = data.parent.parent / "examples" / "scenes" / SCENE_NAME

    def stop(fraction):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        mb.simulate(scene, lmax=3, rays=10**12, points=1, time=0, progress=stop)


def test_sigint_interrupts_a_long_simulation(data):
    scene = data.parent.parent / "examples" / "scenes" / SCENE_NAME
    code = (
        "import sys, microbrdf as mb\n"
        "def p(f):\n"
        "    print('running', flush=True)\n"
        f"mb.simulate({str(scene)!r}, lmax=3, rays=10**12, points=1, progress=p)\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=os.environ)
    assert proc.stdout.readline().strip() == "running"  # inside the C++ loop now
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode != 0 and "KeyboardInterrupt" in err


def test_gil_is_released_during_a_long_call(data):
    # While mb.ndf (Kirchhoff) runs in a thread, the main thread keeps running Python code.
    ticks = [0]
    done = threading.Event()
    marks = []

    def progress(fraction):
        marks.append(ticks[0])

    def work():
        mb.ndf(data / "metropro-1.dat", method="kirchhoff", resolution=129, patch=None,
               progress=progress)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        ticks[0] += 1
    t.join()
    # Between the first progress call (before the transform) and the last one, the main thread
    # advanced: it held the GIL while the C++ code ran.
    assert marks[-1] > marks[0]
