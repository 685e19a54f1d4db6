"""Is the native batch's thread scaling ours or the machine's? `python -m
kiloloop.bench.native_scaling [rounds]` runs quadruped-trot batches (8 rollouts x 4 s, set-up
excluded) in interleaved rounds on persistent worker processes:
  (a) 1 process x 1 thread x 8 rollouts, (b) 1 process x 2 threads x 8, (c) 2 processes x 1 thread
  x 4 each, at the same time,
and prints CPU seconds (process time of the batch calls) and wall seconds, least and median. Equal
CPU in (a), (b) and (c) means threading adds no work (no lock, spinning wait or false sharing);
(b) slower than (c) on the wall clock would point at the process (the batch), both slower than
(a) / 2 at the machine (its other load, shared caches). The load average is printed beside them."""
import json
import os
import statistics
import subprocess
import sys
import time


def _child() -> None:
    from kiloloop.bench.native_quadruped_bench import _rollouts, _setup
    from kiloloop.sil import batch

    rig, cmd = _setup()
    print("ready", flush=True)
    for line in sys.stdin:
        n, threads = map(int, line.split())
        rollouts = _rollouts(rig, cmd, n, 4.0)
        print("built", flush=True)
        sys.stdin.readline()  # go: every worker starts at once
        c, w = time.process_time(), time.perf_counter()
        batch.run(rollouts, threads=threads)
        print(json.dumps({"cpu": time.process_time() - c, "wall": time.perf_counter() - w}), flush=True)


def main(rounds: int = 8) -> dict:
    kids = [subprocess.Popen([sys.executable, "-m", "kiloloop.bench.native_scaling", "child"],
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True) for _ in range(2)]
    for k in kids:
        assert k.stdout.readline().strip() == "ready"

    def go(specs):
        ks = kids[:len(specs)]
        for k, (n, t) in zip(ks, specs):
            k.stdin.write(f"{n} {t}\n")
            k.stdin.flush()
        for k in ks:
            assert k.stdout.readline().strip() == "built"
        for k in ks:
            k.stdin.write("go\n")
            k.stdin.flush()
        return [json.loads(k.stdout.readline()) for k in ks]

    res = {"a": [], "b": [], "c": []}
    loads = [os.getloadavg()[0]]
    for _ in range(rounds):
        res["a"].append(go([(8, 1)])[0])
        res["b"].append(go([(8, 2)])[0])
        r = go([(4, 1), (4, 1)])
        res["c"].append({"cpu": r[0]["cpu"] + r[1]["cpu"], "wall": max(r[0]["wall"], r[1]["wall"])})
    loads.append(os.getloadavg()[0])
    for k in kids:
        k.stdin.close()
        k.wait()
    labels = {"a": "1 process, 1 thread ", "b": "1 process, 2 threads", "c": "2 processes x 4     "}
    for key, runs in res.items():
        cpu, wall = [x["cpu"] for x in runs], [x["wall"] for x in runs]
        print(f"{labels[key]}  CPU min {min(cpu):.3f} median {statistics.median(cpu):.3f} s   "
              f"wall min {min(wall):.3f} median {statistics.median(wall):.3f} s")
    med = {k: statistics.median(x["wall"] for x in v) for k, v in res.items()}
    print(f"wall speed-up over 1 thread (medians): 2 threads {med['a'] / med['b']:.2f}, "
          f"2 processes {med['a'] / med['c']:.2f}; load average before/after {loads[0]:.2f} / {loads[1]:.2f}")
    return {"runs": res, "load_average": loads}


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "child":
        _child()
    else:
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 8)
