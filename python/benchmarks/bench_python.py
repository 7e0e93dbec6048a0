#!/usr/bin/env python3
"""Python batch overhead against the C++ batch, and the Dask example against one process; CSV.

  python3 bench_python.py --bench BUILD/benchmarks/fcl_rs_bench_batch ROBOT.urdf --srdf ROBOT.srdf [--csv FILE]

Overhead: the same configurations (same seed) labelled on one thread by robot.check_batch and by the C++
fcl_rs_bench_batch, process CPU time per batch (load-independent), rounds interleaved (3 warm runs each),
minimum of each.
Dask: python/examples/label_configurations.py's label() on a LocalCluster of 2 worker processes (wall time)
against check_batch on one thread in this process (wall time), same configurations, labels compared.
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import fcl_rs

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
import label_configurations  # noqa: E402


def cpp_cpu_seconds(bench, urdf, srdf, n, seed, repeat):
    with tempfile.NamedTemporaryFile(suffix=".csv") as f:
        subprocess.run([bench, "--robot", urdf] + (["--srdf", srdf] if srdf else []) +
                       ["-n", str(n), "--seed", str(seed), "--threads", "1", "--repeat", str(repeat),
                        "--robot-only", "--distance-configurations", "0", "--csv", f.name],
                       check=True, stdout=subprocess.DEVNULL)
        row = next(csv.DictReader(open(f.name)))
        return float(row["median_cpu_us_per_query"]) * 1e-6 * n


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("urdf")
    parser.add_argument("--srdf", default="")
    parser.add_argument("--bench", required=True, help="the fcl_rs_bench_batch executable")
    parser.add_argument("--sizes", default="1000,10000,100000")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--dask-n", type=int, default=100000)
    parser.add_argument("--csv", default="bench_python.csv")
    args = parser.parse_args()

    robot = fcl_rs.Robot(args.urdf, args.srdf)
    rows = []
    print(f"load average before: {os.getloadavg()}")
    for n in [int(s) for s in args.sizes.split(",")]:
        q = robot.random_configurations(n, 1)
        py, cpp = [], []
        for _ in range(args.rounds):  # interleaved rounds: C++ (median of 3 runs), Python (3 runs: warm, as C++)
            cpp.append(cpp_cpu_seconds(args.bench, args.urdf, args.srdf, n, 1, 3))
            for _ in range(3):
                start = time.process_time()
                robot.check_batch(q, num_threads=1)
                py.append(time.process_time() - start)
        ratio = min(py) / min(cpp)
        print(f"overhead n={n}: python {1e3 * min(py):.2f} ms cpu, C++ {1e3 * min(cpp):.2f} ms cpu, ratio {ratio:.3f}"
              f" (python spread {1e3 * min(py):.2f}..{1e3 * max(py):.2f} ms)")
        rows.append({"measure": "python_over_cpp_cpu", "n": n, "python_s": min(py), "cpp_s": min(cpp),
                     "ratio": ratio})

    from dask.distributed import Client, LocalCluster
    q = robot.random_configurations(args.dask_n, 1)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        label_configurations.label(client, args.urdf, args.srdf, q[:5000])  # workers load the robot
        dask_s, one_s = [], []
        for _ in range(args.rounds):
            start = time.perf_counter()
            labels = label_configurations.label(client, args.urdf, args.srdf, q)
            dask_s.append(time.perf_counter() - start)
            start = time.perf_counter()
            reference = robot.check_batch(q, num_threads=1)["colliding"]
            one_s.append(time.perf_counter() - start)
            assert np.array_equal(labels, reference), "Dask labels differ from one thread's"
    print(f"dask n={args.dask_n}: 2 local workers {min(dask_s):.3f} s ({args.dask_n / min(dask_s):.0f}/s), "
          f"one process {min(one_s):.3f} s ({args.dask_n / min(one_s):.0f}/s), labels equal")
    rows.append({"measure": "dask_2_workers_wall", "n": args.dask_n, "python_s": min(dask_s), "cpp_s": "",
                 "ratio": min(one_s) / min(dask_s)})
    rows.append({"measure": "one_process_wall", "n": args.dask_n, "python_s": min(one_s), "cpp_s": "", "ratio": 1.0})
    print(f"load average after: {os.getloadavg()}")
    with open(args.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["measure", "n", "python_s", "cpp_s", "ratio"])
        w.writeheader()
        w.writerows(rows)
    print(f"CSV written to {args.csv}")


if __name__ == "__main__":
    main()
