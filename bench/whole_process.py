#!/usr/bin/python3
"""Whole-process benchmarks of the command line against the numpy peers in bench/peers/.

Every figure is a whole process, from its start to its files on disk, as a user runs it:
`microbrdf --help`, `info --json`, `ndf --method naive`, `--method filtered` and
`--method kirchhoff --dk-stack single` on generated Gaussian scans (sigma 0.1 um, tau 1 um,
110 nm spacing, seed 1), and beside each its numpy peer (a Python process, `import numpy`
included). Runs alternate between the command and its peer so that both see the same load.
Per command and size: min and median wall time, median user+sys CPU, peak RSS (GNU time, one extra run; see peak_rss), the
time in honest FFT units (bench/fft_unit.cpp, measured in the same session: for info, naive and
filtered the NX x NY complex FFT of the scan's size, for D_K the zero-padded c2c FFT of the tile
as in bench/bench_kirchhoff.cpp; both c2c and r2c figures are in the JSON), the peer's wall time
over the command's, and how far the outputs differ (relative L1 of the tables; for info the
largest relative difference over its statistics). A difference above 1e-3 fails the run (exit
1): the peers are the independent reference. Across sizes: the time exponent in points between
the smallest and the largest size, and memory per point. The load average is recorded.

usage: whole_process.py [--bin DIR] [--sizes 640x480,...] [--runs N] [--commands LIST]
                        [--kirchhoff-sizes LIST] [--quick] [--json FILE] [--workdir DIR]
"""
import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
PEERS = os.path.join(HERE, "peers")
COMMANDS = ["help", "info", "naive", "filtered", "kirchhoff"]
TOLERANCE = 1e-3


def parse_sizes(text):
    sizes = []
    for part in text.split(","):
        nx, _, ny = part.strip().partition("x")
        if not (nx.isdigit() and ny.isdigit()) or int(nx) < 16 or int(ny) < 16:
            raise SystemExit("whole_process.py: error: --sizes: '%s' is not NXxNY (>= 16)" % part)
        sizes.append((int(nx), int(ny)))
    return sizes


def good_size(n):
    """The smallest m >= n with no prime factor above 7 (the library's FFT sizes)."""
    m = n
    while True:
        r = m
        for p in (2, 3, 5, 7):
            while r % p == 0:
                r //= p
        if r == 1:
            return m
        m += 1


def run(argv, stdout=None):
    """One whole process: (wall s, user+sys CPU s, peak RSS bytes); exits on failure."""
    out = open(stdout, "wb") if stdout else subprocess.DEVNULL
    t0 = time.perf_counter()
    p = subprocess.Popen(argv, stdout=out, stderr=subprocess.PIPE)
    err = p.stderr.read()
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    p.returncode = os.waitstatus_to_exitcode(status)
    if stdout:
        out.close()
    if p.returncode != 0:
        sys.stderr.write(err.decode(errors="replace"))
        raise SystemExit("whole_process.py: error: %s exited with %d"
                         % (" ".join(argv), p.returncode))
    return wall, ru.ru_utime + ru.ru_stime, ru.ru_maxrss * 1024


GNU_TIME = "/usr/bin/time"


def peak_rss(argv, stdout=None):
    """Peak RSS in bytes of one more run of argv, measured by GNU time (None without it).

    os.wait4 cannot give it for small processes: a child forked from this Python process starts
    with the parent's resident pages (about 33 MB), and Linux keeps that high-water mark across
    exec, so every command would seem to need at least that much. GNU time's own child is forked
    from a process of about 2 MB. A separate run, so that the timed runs carry no wrapper."""
    if not os.path.exists(GNU_TIME):
        return None
    with tempfile.NamedTemporaryFile("r", suffix=".rss") as f:
        run([GNU_TIME, "-f", "%M", "-o", f.name] + argv, stdout)
        return int(f.read().split()[-1]) * 1024


def fft_unit(binary, args, rounds=1):
    """The least best_ms of `rounds` runs of microbrdf_fft_unit with these arguments (None
    without the binary). Each run plans anew with FFTW_MEASURE, and on a loaded machine the plan
    it keeps and its timings vary (10.4 to 15.4 ms for one 1280 x 960 c2c in five runs in a
    row): the fastest of several is the yardstick, so that a slow unit cannot flatter the CLI."""
    if not binary:
        return None
    best = None
    for _ in range(rounds):
        r = subprocess.run([binary] + args, capture_output=True, text=True, check=True)
        ms = json.loads(r.stdout)["best_ms"]
        best = ms if best is None else min(best, ms)
    return best


def units_for(binary, nx, ny, quick, dk):
    """The honest units of one size (the zero-padded D_K unit only if `dk`)."""
    reps = ["--runs", "5" if quick else "30"]
    rounds = 1 if quick else 4
    px, py = good_size(2 * nx), good_size(2 * ny)
    return {"c2c": fft_unit(binary, [str(nx), str(ny)] + reps, rounds),
            "r2c": fft_unit(binary, [str(nx), str(ny), "--r2c"] + reps, rounds),
            "dk_c2c": fft_unit(binary, [str(px), str(py), "--phasor", "--data",
                                        "%dx%d" % (nx, ny)] + reps, rounds) if dk else None,
            "dk_shape": "%dx%d" % (px, py)}


def invocations(cmd, cli, python, scan, work, tag):
    """(CLI argv, CLI stdout file or None, CLI output, peer argv, peer output) of one command."""
    out = os.path.join(work, "cli_%s_%s" % (cmd, tag))
    peer = os.path.join(work, "peer_%s_%s" % (cmd, tag))
    if cmd == "help":
        return [cli, "--help"], None, None, [python, "-c", "import numpy"], None
    if cmd == "info":
        return ([cli, "info", scan, "--json"], out + ".json", out + ".json",
                [python, os.path.join(PEERS, "info.py"), scan, peer + ".json"], peer + ".json")
    script = {"naive": "naive_ndf.py", "filtered": "filtered_ndf.py", "kirchhoff": "dk.py"}[cmd]
    argv = [cli, "ndf", scan, "--method", cmd, "-o", out + ".npy"]
    if cmd == "kirchhoff":
        argv += ["--dk-stack", "single"]
    return (argv, None, out + ".npy",
            [python, os.path.join(PEERS, script), scan, peer + ".npy"], peer + ".npy")


def flat_numbers(d, prefix=""):
    out = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out.update(flat_numbers(v, prefix + k + "."))
        elif isinstance(v, list):
            for i, x in enumerate(v):
                if isinstance(x, dict):
                    out.update(flat_numbers(x, "%s%s[%d]." % (prefix, k, i)))
        elif isinstance(v, (int, float)) and not isinstance(v, bool):
            out[prefix + k] = float(v)
    return out


def difference(cmd, cli_out, peer_out):
    """Relative L1 of the tables; for info the largest relative difference over the peer's
    statistics (the mean height, 0 up to rounding, relative to Sq). Also what was compared."""
    if cmd == "info":
        a = flat_numbers(json.load(open(cli_out))["surfaces"][0])
        b = flat_numbers(json.load(open(peer_out))["surfaces"][0])
        worst, n = 0.0, 0
        for k, v in b.items():
            if k not in a:
                raise SystemExit("whole_process.py: error: info --json has no '%s'" % k)
            scale = abs(a["sq_m"]) if k == "mean_m" else abs(a[k])
            d = abs(a[k] - v) / scale if scale > 0 else abs(a[k] - v)
            worst, n = max(worst, d), n + 1
        return worst, "max relative difference over %d statistics" % n
    a, b = np.load(cli_out), np.load(peer_out)
    if a.shape != b.shape:
        raise SystemExit("whole_process.py: error: %s is %s, its peer's table %s"
                         % (cli_out, a.shape, b.shape))
    return float(np.abs(a - b).sum() / np.abs(a).sum()), "relative L1 of the %dx%d table" % a.shape


def summary(samples):
    walls = [s[0] for s in samples]
    return {"wall_min_s": min(walls), "wall_median_s": statistics.median(walls),
            "cpu_median_s": statistics.median(s[1] for s in samples),
            "rss_peak_mb": max(s[2] for s in samples) / 2**20, "runs": len(samples)}


def exponent(rows, key):
    """Time exponent in points between the smallest and largest size, and memory per point."""
    if len(rows) < 2:
        return None
    a, b = rows[0], rows[-1]
    pa, pb = a["points"], b["points"]
    ta, tb = a[key]["wall_median_s"], b[key]["wall_median_s"]
    ma, mb = a[key]["rss_peak_mb"] * 2**20, b[key]["rss_peak_mb"] * 2**20
    return {"from": a["size"], "to": b["size"], "exponent": math.log(tb / ta) / math.log(pb / pa),
            "bytes_per_point": mb / pb, "marginal_bytes_per_point": (mb - ma) / (pb - pa)}


def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def markdown(result):
    lines = ["| size | command | wall min / median (s) | CPU (s) | peak RSS (MB) | FFT units "
             "(min wall) | numpy peer wall min / median (s) | peer RSS (MB) | peer / CLI "
             "(median) | difference |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in result["rows"]:
        c, p = r["cli"], r.get("peer")
        lines.append("| %s | %s | %.3f / %.3f | %.3f | %.0f | %s | %s | %s | %s | %s |" % (
            r["size"], r["command"], c["wall_min_s"], c["wall_median_s"], c["cpu_median_s"],
            c["rss_peak_mb"], fmt(r.get("fft_units_min"), ".1f"),
            "%.3f / %.3f" % (p["wall_min_s"], p["wall_median_s"]) if p else "-",
            "%.0f" % p["rss_peak_mb"] if p else "-", fmt(r.get("peer_over_cli"), ".2f") + "x"
            if r.get("peer_over_cli") else "-", fmt(r.get("difference"), ".1e")))
    if result["scaling"]:
        lines += ["", "| command | who | time exponent in points | bytes per point (largest) | "
                  "marginal bytes per point |", "|---|---|---|---|---|"]
        for s in result["scaling"]:
            lines.append("| %s | %s | %.2f (%s to %s) | %.0f | %.0f |" % (
                s["command"], s["who"], s["exponent"], s["from"], s["to"], s["bytes_per_point"],
                s["marginal_bytes_per_point"]))
    u = "; ".join("%s: c2c %s ms, r2c %s ms%s" % (
        k, fmt(v["c2c"], ".2f"), fmt(v["r2c"], ".2f"), ", D_K c2c %s %s ms" % (
            v["dk_shape"], fmt(v["dk_c2c"], ".2f")) if v["dk_c2c"] else "")
        for k, v in result["units"].items())
    lines += ["", "FFT units (best of the runs, FFTW_MEASURE, 2 FFTW threads): %s. Load average "
              "%.2f before, %.2f after." % (u, result["load_before"], result["load_after"])]
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    root = os.path.dirname(HERE)
    ap.add_argument("--bin", default=os.path.join(root, "build", "bin"),
                    help="folder of microbrdf and microbrdf_fft_unit (default build/bin)")
    ap.add_argument("--sizes", default="640x480,1280x960,2560x1920")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--commands", default=",".join(COMMANDS))
    ap.add_argument("--kirchhoff-sizes", default=None,
                    help="sizes D_K runs on (default: the smallest of --sizes)")
    ap.add_argument("--quick", action="store_true",
                    help="one run on a 128x96 scan (unless --sizes/--runs say otherwise)")
    ap.add_argument("--json", help="write the results here too")
    ap.add_argument("--workdir", help="keep scans and outputs here (default: a temporary folder)")
    ap.add_argument("--python", default="/usr/bin/python3", help="the peers' interpreter")
    a = ap.parse_args()
    if a.quick:
        if a.sizes == ap.get_default("sizes"):
            a.sizes = "128x96"
        if a.runs == ap.get_default("runs"):
            a.runs = 1
    sizes = parse_sizes(a.sizes)
    sizes.sort(key=lambda s: s[0] * s[1])
    dk_sizes = parse_sizes(a.kirchhoff_sizes) if a.kirchhoff_sizes else sizes[:1]
    commands = [c.strip() for c in a.commands.split(",")]
    for c in commands:
        if c not in COMMANDS:
            raise SystemExit("whole_process.py: error: --commands: unknown '%s' (%s)"
                             % (c, ", ".join(COMMANDS)))
    if a.runs < 1:
        raise SystemExit("whole_process.py: error: --runs must be >= 1")
    cli = os.path.join(a.bin, "microbrdf")
    if not os.access(cli, os.X_OK):
        raise SystemExit("whole_process.py: error: --bin: no microbrdf in %s" % a.bin)
    unit_bin = os.path.join(a.bin, "microbrdf_fft_unit")
    if not os.access(unit_bin, os.X_OK):
        print("whole_process.py: note: no microbrdf_fft_unit in %s (build the target "
              "microbrdf_fft_unit): no FFT units" % a.bin, file=sys.stderr)
        unit_bin = None
    work = a.workdir or tempfile.mkdtemp(prefix="microbrdf-whole-")
    os.makedirs(work, exist_ok=True)
    result = {"settings": {"sizes": ["%dx%d" % s for s in sizes], "runs": a.runs,
                           "commands": commands, "kirchhoff_sizes": ["%dx%d" % s for s in dk_sizes],
                           "scan": "generate gaussian --sigma 0.1um --tau 1um --spacing 110nm "
                                   "--seed 1", "cores": os.cpu_count()},
              "load_before": os.getloadavg()[0], "units": {}, "rows": [], "scaling": []}
    failed = []
    try:
        for nx, ny in sizes:
            tag = "%dx%d" % (nx, ny)
            scan = os.path.join(work, "scan_%s.npy" % tag)
            run([cli, "generate", "gaussian", "--sigma", "0.1um", "--tau", "1um", "--spacing",
                 "110nm", "--nx", str(nx), "--ny", str(ny), "--seed", "1", "-o", scan])
            todo = [c for c in commands if (c != "kirchhoff" or (nx, ny) in dk_sizes)
                    and (c != "help" or (nx, ny) == sizes[0])]
            # Measured before and after the runs; the best of both is the unit.
            units = units_for(unit_bin, nx, ny, a.quick, "kirchhoff" in todo)
            load0 = os.getloadavg()[0]
            samples = {c: ([], []) for c in todo}
            for _ in range(a.runs):  # rounds: every command and its peer once per round
                for c in todo:
                    argv, stdout, _, pargv, _ = invocations(c, cli, a.python, scan, work, tag)
                    samples[c][0].append(run(argv, stdout))
                    samples[c][1].append(run(pargv))
            rss = {}
            for c in todo:
                argv, stdout, _, pargv, _ = invocations(c, cli, a.python, scan, work, tag)
                rss[c] = (peak_rss(argv, stdout), peak_rss(pargv))
            after = units_for(unit_bin, nx, ny, a.quick, "kirchhoff" in todo)
            for k in ("c2c", "r2c", "dk_c2c"):
                if units[k] is not None:
                    units[k] = min(units[k], after[k])
            result["units"][tag] = units
            for c in todo:
                _, _, out, _, pout = invocations(c, cli, a.python, scan, work, tag)
                row = {"size": tag, "points": nx * ny, "command": c,
                       "load_before": load0, "load_after": os.getloadavg()[0],
                       "cli": summary(samples[c][0]), "peer": summary(samples[c][1])}
                for who, probe in zip(("cli", "peer"), rss[c]):
                    if probe is not None:  # (else the wait4 figure, an upper bound)
                        row[who]["rss_peak_mb"] = probe / 2**20
                        row[who]["rss_by"] = "GNU time, one more run"
                unit = units["dk_c2c"] if c == "kirchhoff" else units["c2c"]
                if unit and c != "help":
                    row["fft_unit"] = ("c2c %s, phasor fill" % units["dk_shape"]
                                       if c == "kirchhoff" else "c2c %s, copy fill" % tag)
                    row["fft_units_min"] = row["cli"]["wall_min_s"] * 1e3 / unit
                    row["fft_units_median"] = row["cli"]["wall_median_s"] * 1e3 / unit
                    if c != "kirchhoff":  # the same scan in the r2c unit (about half the c2c)
                        row["r2c_units_min"] = row["cli"]["wall_min_s"] * 1e3 / units["r2c"]
                row["peer_over_cli"] = row["peer"]["wall_median_s"] / row["cli"]["wall_median_s"]
                row["peer_over_cli_min"] = row["peer"]["wall_min_s"] / row["cli"]["wall_min_s"]
                if out:
                    row["difference"], row["compared"] = difference(c, out, pout)
                    if not row["difference"] <= TOLERANCE:
                        failed.append("%s %s: %s %.3g > %g" % (c, tag, row["compared"],
                                                                row["difference"], TOLERANCE))
                result["rows"].append(row)
    finally:
        if not a.workdir:
            shutil.rmtree(work, ignore_errors=True)
    for c in commands:
        rows = [r for r in result["rows"] if r["command"] == c]
        for who in ("cli", "peer"):
            s = exponent(rows, who)
            if s:
                result["scaling"].append(dict(s, command=c, who=who))
    result["load_after"] = os.getloadavg()[0]
    result["failed"] = failed
    print(markdown(result))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=1)
    for f in failed:
        print("whole_process.py: FAIL: the CLI and its numpy peer differ: %s" % f, file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
