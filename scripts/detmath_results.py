#!/usr/bin/env python3
"""Runs kiloloop_bench_detmath (musl's C math against glibc: ulp error against
quadruple precision, ns per call) and writes its two tables into bench/RESULTS.md as a dated
section, replacing that date's section if there is one.

    python scripts/detmath_results.py [--exe PATH] [--args N] [--out bench/RESULTS.md] [--print]
"""
from __future__ import annotations

import argparse
import datetime
import os
import platform
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TITLE = "## Deterministic math: musl's C math against glibc"
NO_FMA = "glibc.cpu.hwcaps=-AVX2,-FMA"


def default_exe() -> Path:
    from importlib.resources import files
    return Path(str(files("kiloloop") / "bin" / "kiloloop_bench_detmath"))


def cpu_model() -> str:
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("model name"):
            return line.split(":", 1)[1].strip()
    return platform.processor() or "unknown CPU"


def _rows(table: str) -> list[list[str]]:
    return [[c.strip() for c in line.strip().strip("|").split("|")]
            for line in table.splitlines() if line.startswith("| ") and "---" not in line]


def section(table: str, no_fma_table: str, n_args: int, exe_rc: int, load: tuple,
            today: str) -> str:
    rows = _rows(table)
    head, body = rows[0], rows[1:]
    nf = _rows(no_fma_table)
    glibc_nf = {r[0]: r[nf[0].index("glibc ns")] for r in nf[1:]}
    head.append("glibc ns, no FMA/AVX2")
    for r in body:
        r.append(glibc_nf.get(r[0], "-"))
    acc = ["function", "range", "arguments", "musl max ulp", "musl ulps from rounded",
           "musl not correctly rounded", "glibc max ulp", "glibc not correctly rounded"]
    speed = ["function", "musl ns", "glibc ns", "musl / glibc", "glibc ns, no FMA/AVX2"]

    def render(cols):
        idx = [head.index(c) for c in cols]
        out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
        out += ["| " + " | ".join(r[i] for i in idx) + " |" for r in body]
        return "\n".join(out)

    worst = max(float(r[head.index("musl max ulp")]) for r in body)
    beyond = [r[0] for r in body if int(r[head.index("musl ulps from rounded")]) > 1]
    over = [r[0] for r in body if float(r[head.index("musl / glibc")]) > 1.5]
    return f"""{TITLE} ({today})
`python scripts/detmath_results.py` (`kiloloop_bench_detmath --args {n_args}`, bench/bench_detmath.cpp):
musl 1.2.5's C math as kiloloop_libm builds it (`-O2 -ffp-contract=off -U__FP_FAST_FMA`, no
FMA, no SIMD; cmake/detmath.cmake) against glibc {platform.libc_ver()[1]} on this CPU ({cpu_model()};
glibc picks its FMA/AVX2 code paths here). Accuracy: {n_args:,} seeded arguments per function over
the ranges the real-time code calls it on, each result against libquadmath's quadruple precision,
error in ulps of the double nearest the exact value (0.5 = correctly rounded at worst), and the
largest distance from the correctly rounded double in ulps (how many doubles apart). Speed:
median ns per call of 15 loops of 100,000 calls on distinct arguments (load average
{load[0]:.1f} at the start: the ns are noisy on this shared VM, the ratios less so); the last
column is glibc once more with `GLIBC_TUNABLES={NO_FMA}` (the code a CPU without FMA runs).

Largest musl error: {worst:.3f} ulp. More than 1 ulp from the correctly rounded result (issue 31's
bound; the program exits {exe_rc}): {", ".join(beyond) if beyond else "none"}.
{"Over 1.5x glibc's time: " + ", ".join(over) + "." if over else "Every function within 1.5x of glibc's time."}

{render(acc)}

{render(speed)}
"""


def write(results: Path, text: str, today: str) -> None:
    old = results.read_text()
    pattern = re.compile(rf"^{re.escape(TITLE)} \({today}\)\n.*?(?=^#{{1,3}} |\Z)",
                         re.MULTILINE | re.DOTALL)
    new = pattern.sub(lambda _: text + "\n", old) if pattern.search(old) else \
        old.rstrip("\n") + "\n\n" + text
    results.write_text(new)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--exe", type=Path, default=None)
    ap.add_argument("--args", type=int, default=2_000_000)
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "RESULTS.md")
    ap.add_argument("--print", action="store_true", help="print the section, write nothing")
    a = ap.parse_args(argv)
    exe = a.exe or default_exe()
    load = os.getloadavg()
    proc = subprocess.run([str(exe), "--args", str(a.args)], capture_output=True, text=True)
    # glibc's speed once more with its FMA/AVX2 code paths off (what a CPU without them gets)
    no_fma = subprocess.run([str(exe), "--args", "0"], capture_output=True, text=True,
                            env=dict(os.environ, GLIBC_TUNABLES=NO_FMA))
    if proc.returncode not in (0, 1) or "| function |" not in proc.stdout + no_fma.stdout:
        print(proc.stdout + proc.stderr, file=sys.stderr)
        return 2
    today = datetime.date.today().isoformat()
    text = section(proc.stdout, no_fma.stdout, a.args, proc.returncode, load, today)
    if a.print:
        print(text)
    else:
        write(a.out, text, today)
        print(f"wrote {TITLE[3:]} ({today}) into {a.out}")
    print(text if not a.print else "", end="")
    return proc.returncode


if __name__ == "__main__":
    sys.exit(main())
