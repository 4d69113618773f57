#!/usr/bin/python3
"""Runs the command blocks of the documentation, as a reader copying them would.

    run_doc_blocks.py --source REPO --build BUILD [--keep] [--list] FILE.md ...

Every fenced block of each Markdown file is classified by its language:

  sh, console, python, pycon   run, in document order, in one fresh folder per file (a later
                               block may use a file an earlier block made, as a reader's would)
  cpp                          compiled (g++ -fsyntax-only, statements wrapped in main) against
                               the repository's headers when marked `<!-- doc-test: compile -->`
  cmake                        must be marked `<!-- doc-test: covered-by: PATH -->` (a test that
                               runs the same code; PATH must exist)
  text, csv, json, ...         not commands; a line that starts like a command is an error (a
                               command block must not hide under another label)
  no label                     an error: every block says what it is

The folder looks like the repository root (README: "from the repository root"): its top-level
entries link to the repository's (read-only use), `build/bin` and `build/python` to the build,
and `docs/img` is a copy (blocks read its textures and write figures there), so that nothing a
block writes lands in the sources.
`microbrdf` is on PATH and the module on PYTHONPATH; `python3` is /usr/bin/python3.

Annotations: an HTML comment on the lines just above a block (blank lines allowed between):
  <!-- doc-test: skip: REASON -->       not run; counted and printed with the reason
  <!-- doc-test: expect "REGEX" -->     the block's output (stdout + stderr) must match (re.search,
                                        MULTILINE); several allowed
  <!-- doc-test: timeout SECONDS -->    per block (default 300 s)
  <!-- doc-test: requires: PROGRAM -->  skipped (counted, with the reason) when PROGRAM is not on
                                        PATH (e.g. chromium, which `make test` does not need)

Checked output:
  console  `$ command` lines (continued with a trailing backslash) are run one after the other;
           the lines below a command up to the next `$` are its output: compared line by line
           with runs of spaces folded and every number equal to the digits printed (a line
           `...` matches any number of lines).
  pycon    run with doctest (`>>>` / `...` prompts, the output below), ELLIPSIS and
           NORMALIZE_WHITESPACE: the shown values are the computed ones.
Exit status: 0 when every block that is not skipped passed, 1 otherwise.
"""
import argparse
import doctest
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

PYTHON = "/usr/bin/python3"
RUN_LANGS = {"sh", "console", "python", "pycon"}
CHECK_LANGS = {"cpp", "cmake"}
# The start of a line that is a command, in a block labelled as something else.
COMMAND_START = re.compile(r"^(?!.*: error: )\s*(\$ |microbrdf [a-z]|mpirun |srun |sbatch |make |ctest |cmake |"
                           r"PYTHONPATH=|build/bin/|/usr/bin/python3 )")
ANNOTATION = re.compile(r"^<!--\s*doc-test:\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)(```+)\s*([^\s`]*)\s*$")


class Block:
    def __init__(self, path, line, lang, text, notes):
        self.path, self.line, self.lang, self.text, self.notes = path, line, lang, text, notes

    def where(self):
        return f"{self.path}:{self.line}"

    def note(self, key):
        return [v for k, v in self.notes if k == key]


def parse_note(text):
    """'skip: reason' -> ('skip', 'reason'); 'expect "re"' -> ('expect', 're')."""
    m = re.match(r'(skip|covered-by|requires)\s*:\s*(.+)$', text)
    if m:
        return m.group(1), m.group(2)
    m = re.match(r'expect\s+"(.*)"$', text)
    if m:
        return "expect", m.group(1)
    m = re.match(r'timeout\s+(\d+)$', text)
    if m:
        return "timeout", m.group(1)
    if text == "compile":
        return "compile", ""
    raise ValueError(f"unknown doc-test annotation: {text!r}")


def blocks_of(path, display):
    lines = open(path, encoding="utf-8").read().split("\n")
    out, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, ticks, lang = m.group(1), m.group(2), m.group(3).lower()
        j = i + 1
        while j < len(lines) and not re.match(r"^\s*" + ticks + r"\s*$", lines[j]):
            j += 1
        if j == len(lines):
            raise ValueError(f"{display}:{i + 1}: unclosed code fence")
        body = [l[len(indent):] if l.startswith(indent) else l.lstrip() for l in lines[i + 1:j]]
        notes, k = [], i - 1
        while k >= 0 and (not lines[k].strip() or ANNOTATION.match(lines[k].strip())):
            a = ANNOTATION.match(lines[k].strip())
            if a:
                notes.insert(0, parse_note(a.group(1)))
            k -= 1
        out.append(Block(display, i + 1, lang, "\n".join(body) + "\n", notes))
        i = j + 1
    return out


def make_workdir(source, build):
    """A folder that looks like the repository root, writes staying inside it."""
    work = tempfile.mkdtemp(prefix="doc-blocks-")
    for entry in os.listdir(source):
        if entry in (".git", "docs") or entry.startswith("build") or entry == "demo-out":
            continue
        os.symlink(os.path.join(source, entry), os.path.join(work, entry))
    # A copy of docs/img: blocks read its textures and write figures into it.
    shutil.copytree(os.path.join(source, "docs", "img"), os.path.join(work, "docs", "img"))
    for entry in os.listdir(os.path.join(source, "docs")):
        if entry != "img":
            os.symlink(os.path.join(source, "docs", entry), os.path.join(work, "docs", entry))
    # build/bin holds links to the programs, not a link to the folder: a stray build in the work
    # folder replaces a link, never a program of the real build.
    os.makedirs(os.path.join(work, "build", "bin"))
    for entry in os.listdir(os.path.join(build, "bin")):
        os.symlink(os.path.join(build, "bin", entry), os.path.join(work, "build", "bin", entry))
    os.symlink(os.path.join(build, "python"), os.path.join(work, "build", "python"))
    return work


def environment(build):
    env = dict(os.environ)
    shim = tempfile.mkdtemp(prefix="doc-blocks-bin-")  # `python3` is the system's, with numpy
    os.symlink(PYTHON, os.path.join(shim, "python3"))
    env["PATH"] = os.pathsep.join([os.path.join(build, "bin"), shim, env.get("PATH", "")])
    env["PYTHONPATH"] = os.path.join(build, "python")
    env["MICROBRDF_CLI"] = os.path.join(build, "bin", "microbrdf")
    env["MPLBACKEND"] = "Agg"
    # A doc's `mpirun -np 4` as the reader types it: the suite may run as root (containers) and
    # on fewer cores than ranks; Open MPI refuses both unless told (tests/mpi pass the flags).
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    env.pop("MAKEFLAGS", None)
    return env, shim


def run(argv_or_script, cwd, env, timeout, shell=True):
    t0 = time.monotonic()
    p = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", argv_or_script] if shell else argv_or_script,
                       cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       timeout=timeout)
    return p.returncode, p.stdout.decode("utf-8", "replace"), time.monotonic() - t0


NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


def same_line(expected, got):
    """Text equal with runs of spaces folded; each number equal to the digits the doc prints."""
    e, g = " ".join(expected.split()), " ".join(got.split())
    if NUMBER.sub("#", e) != NUMBER.sub("#", g):
        return False
    for a, b in zip(NUMBER.findall(e), NUMBER.findall(g)):
        if a != b and float(a) != float(b):
            return False
    return True


def match_output(expected, got):
    """Line-by-line comparison; a line '...' matches any number of lines. Returns a message."""
    exp = [l for l in expected if l.strip()]
    out = [l for l in got if l.strip()]

    def walk(i, j):
        if i == len(exp):
            return None if j == len(out) else f"unexpected output line: {out[j]!r}"
        if exp[i].strip() == "...":
            for jj in range(j, len(out) + 1):
                if walk(i + 1, jj) is None:
                    return None
            return f"no match for the lines after '...' (from {exp[i + 1]!r})" if i + 1 < len(exp) else None
        if j == len(out):
            return f"missing output line: {exp[i]!r}"
        if not same_line(exp[i], out[j]):
            return f"the doc shows\n    {exp[i]}\n  the run printed\n    {out[j]}"
        return walk(i + 1, j + 1)

    return walk(0, 0)


def console_steps(text):
    """[(command, [expected output lines])] of a console block."""
    steps, lines = [], text.split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("$ "):
            cmd = line[2:]
            while cmd.endswith("\\") and i + 1 < len(lines):
                i += 1
                cmd = cmd[:-1] + "\n" + lines[i]
            steps.append((cmd, []))
        elif steps:
            steps[-1][1].append(line)
        elif line.strip():
            raise ValueError(f"console block: output before the first '$ ' line: {line!r}")
        i += 1
    return steps


# Lines that build, install or run the whole suite: never run from here (a `make` in the work
# folder would build a second tree; `make test` would run this runner again).
NOT_HERE = re.compile(r"^\s*(\$ )?(make|sudo|apt|apt-get|ctest|cmake --build|cmake --install)\b")


def run_block(b, work, env, source):
    """Returns (ok, output, message)."""
    if b.lang in ("sh", "console"):
        bad = [l for l in b.text.split("\n") if NOT_HERE.match(l)]
        if bad:
            return False, "", (f"{bad[0].strip()!r} builds, installs or runs the suite: mark the "
                               "block `<!-- doc-test: skip: REASON -->`, or move the line out")
    timeout = int((b.note("timeout") or ["300"])[0])
    if b.lang == "sh":
        # Each command echoed with the time it started (the log of a failure shows which one).
        rc, out, _ = run("PS4='+ [$SECONDS s] '; set -x\n" + b.text, work, env, timeout)
        return rc == 0, out, f"exit status {rc}"
    if b.lang == "python":
        rc, out, _ = run([PYTHON, "-c", b.text], work, env, timeout, shell=False)
        return rc == 0, out, f"exit status {rc}"
    if b.lang == "console":
        log = ""
        for cmd, expected in console_steps(b.text):
            rc, out, _ = run(cmd, work, env, timeout)
            log += f"$ {cmd}\n{out}"
            if rc != 0:
                return False, log, f"`{cmd}`: exit status {rc}"
            if expected:
                problem = match_output(expected, out.split("\n"))
                if problem:
                    return False, log, f"`{cmd}`: {problem}"
        return True, log, ""
    if b.lang == "pycon":
        script = ("import doctest, sys\n"
                  "t = doctest.DocTestParser().get_doctest(sys.stdin.read(), {}, 'doc', 'doc', 0)\n"
                  "r = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)\n"
                  "r.run(t)\nsys.exit(1 if r.failures else 0)\n")
        p = subprocess.run([PYTHON, "-c", script], input=b.text.encode(), cwd=work, env=env,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout)
        return p.returncode == 0, p.stdout.decode("utf-8", "replace"), "doctest failed"
    if b.lang == "cpp":
        includes = [l for l in b.text.split("\n") if l.startswith("#include")]
        body = [l for l in b.text.split("\n") if not l.startswith("#include")]
        src = os.path.join(work, "doc_block.cpp")
        with open(src, "w") as f:
            f.write("\n".join(includes) + "\nint main() {\n" + "\n".join(body) + "\n(void)0;\n}\n")
        cmd = ["g++", "-std=c++20", "-fsyntax-only", "-Wall", "-Wno-unused-variable",
               "-I", os.path.join(source, "include"), "-I", "/usr/include/eigen3", src]
        rc, out, _ = run(cmd, work, env, timeout, shell=False)
        return rc == 0, out, f"g++ exit status {rc}"
    raise AssertionError(b.lang)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("--source", required=True, help="repository root")
    ap.add_argument("--build", required=True, help="build folder (bin/microbrdf, python/)")
    ap.add_argument("--keep", action="store_true", help="keep the work folders")
    ap.add_argument("--list", action="store_true", help="list the blocks, run nothing")
    ap.add_argument("-v", "--verbose", action="store_true", help="print every block's output")
    ap.add_argument("files", nargs="+")
    a = ap.parse_args()
    sys.stdout.reconfigure(line_buffering=True)  # progress visible under ctest -V
    source, build = os.path.abspath(a.source), os.path.abspath(a.build)
    env, shim = environment(build)
    totals = dict(ran=0, passed=0, skipped=0, checked=0, other=0)
    failures = []
    for f in a.files:
        path = f if os.path.isabs(f) else os.path.join(source, f)
        display = os.path.relpath(path, source)
        blocks = blocks_of(path, display)
        work = None if a.list else make_workdir(source, build)
        t_file = time.monotonic()
        for b in blocks:
            skip = b.note("skip")
            for prog in b.note("requires"):
                if not shutil.which(prog, path=env["PATH"]):
                    skip = [f"needs {prog}, not installed here"]
            if b.lang == "":
                failures.append((b, "", "a block without a language: label it (sh, console, "
                                        "python, pycon, text, ...)"))
                continue
            if b.lang not in RUN_LANGS | CHECK_LANGS:
                bad = [l for l in b.text.split("\n") if COMMAND_START.match(l)]
                if bad and not skip:
                    failures.append((b, "", f"a `{b.lang}` block holds a command line: {bad[0]!r} "
                                            "(label it sh/console, or mark it skip with a reason)"))
                totals["other"] += 1
                continue
            if skip:
                totals["skipped"] += 1
                print(f"SKIP {b.where()} [{b.lang}]: {skip[0]}")
                continue
            if b.lang == "cmake" or (b.lang == "cpp" and not b.note("compile")):
                cov = b.note("covered-by")
                if not cov:
                    failures.append((b, "", f"a `{b.lang}` block needs `<!-- doc-test: compile -->`"
                                            " or `<!-- doc-test: covered-by: PATH -->`"))
                    continue
                target = cov[0].split()[0]
                if not os.path.exists(os.path.join(source, target)):
                    failures.append((b, "", f"covered-by: {target} does not exist"))
                    continue
                totals["checked"] += 1
                print(f"COVERED {b.where()} [{b.lang}] by {cov[0]}")
                continue
            if a.list:
                print(f"RUN {b.where()} [{b.lang}]")
                totals["ran"] += 1
                continue
            t0 = time.monotonic()
            try:
                ok, out, msg = run_block(b, work, env, source)
            except subprocess.TimeoutExpired as e:
                ok, out, msg = False, "", f"timed out after {e.timeout} s"
            for rx in b.note("expect"):
                if ok and not re.search(rx, out, re.MULTILINE):
                    ok, msg = False, f'expected output matching "{rx}"'
            totals["ran"] += 1
            dt = time.monotonic() - t0
            if ok:
                totals["passed"] += 1
                print(f"ok   {b.where()} [{b.lang}] {dt:.1f} s")
                if a.verbose:
                    print("\n".join("  | " + l for l in out.rstrip().split("\n")))
            else:
                failures.append((b, out, msg))
                print(f"FAIL {b.where()} [{b.lang}] {dt:.1f} s: {msg.splitlines()[0] if msg else ''}")
        if work:
            print(f"{display}: {len(blocks)} blocks, {time.monotonic() - t_file:.1f} s"
                  + (f", kept in {work}" if a.keep else ""))
            if not a.keep:
                shutil.rmtree(work, ignore_errors=True)
    shutil.rmtree(shim, ignore_errors=True)
    print(f"\ncommand blocks: {totals['ran']} run, {totals['passed']} passed, {totals['skipped']} "
          f"skipped, {totals['checked']} covered by other tests; {totals['other']} other blocks "
          f"(text, tables, formats); {len(failures)} failure(s)")
    for b, out, msg in failures:
        print(f"\n=== FAILED {b.where()} [{b.lang}]: {msg}")
        tail = out.strip().split("\n")[-40:]
        if out.strip():
            print("\n".join("  | " + l for l in tail))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
