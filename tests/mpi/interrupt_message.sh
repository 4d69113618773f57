#!/usr/bin/env bash
# SIGINT to mpirun: every rank ends, no output or temporary is left, and the run says once
# (rank 0 alone) that it was interrupted, instead of ending without a word.
set -u
BIN=$(realpath "$1")
MPIRUN=$2
HERE=$(cd "$(dirname "$0")" && pwd)
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
/usr/bin/python3 - "$BIN" "$MPIRUN" "$T" "$HERE/../../examples/scenes/cylinders.json" <<'PY' || exit 1
import os, signal, subprocess, sys, time
bin, mpirun, t, scene = sys.argv[1:5]
cmd = [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", "2", bin, "simulate", scene,
       "--rays", "2000000000", "-o", t + "/never.shbrdf"]
p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=t)
time.sleep(4)  # past MPI start-up: the ranks are tracing
assert p.poll() is None, "the run ended by itself: " + p.stderr.read().decode()
p.send_signal(signal.SIGINT)
try:
    err = p.communicate(timeout=60)[1].decode(errors="replace")
except subprocess.TimeoutExpired:
    p.kill()
    sys.exit("FAIL: mpirun still running 60 s after SIGINT")
print(err)
assert p.returncode != 0, "FAIL: exit 0 after SIGINT"
n = err.count("microbrdf: interrupted")
assert n == 1, f"FAIL: 'interrupted' said {n} times (want once, by rank 0)"
left = os.listdir(t)
assert not left, f"FAIL: left behind: {left}"
print("ok")
PY
