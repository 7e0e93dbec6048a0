#!/usr/bin/env python3
"""Labels random configurations of a URDF robot as self-colliding or free, with Dask.

Configurations are cut into chunks; each Dask worker loads the robot once (per worker process) and labels
the chunks it is given; the labels are gathered into one array in the configurations' order.

  python3 label_configurations.py ROBOT.urdf [--srdf ROBOT.srdf] [-n 100000] [--workers 2]
  python3 label_configurations.py ROBOT.urdf --scheduler tcp://HOST:8786     # a running Dask cluster

Without --scheduler a LocalCluster on the loopback interface is started. On a cluster every worker needs the
fcl_rs module and the robot files at the same paths.
"""
import argparse
import functools
import time

import numpy as np

import fcl_rs


@functools.lru_cache(maxsize=None)
def load_robot(urdf, srdf):
    """One robot per worker process (threads of a worker share it: queries only read it)."""
    return fcl_rs.Robot(urdf, srdf)


def label_chunk(urdf, srdf, configurations):
    # One thread per task: Dask already runs one task per worker thread.
    return load_robot(urdf, srdf).check_batch(configurations, num_threads=1)["colliding"]


def label(client, urdf, srdf, configurations, chunk_size=5000):
    """Self-collision labels (N,) bool of (N, dof) configurations, computed on the client's workers."""
    chunks = [configurations[i:i + chunk_size] for i in range(0, len(configurations), chunk_size)]
    futures = client.map(label_chunk, [urdf] * len(chunks), [srdf] * len(chunks), chunks, pure=False)
    return np.concatenate(client.gather(futures)) if chunks else np.zeros(0, dtype=bool)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("urdf")
    parser.add_argument("--srdf", default="", help="SRDF with disabled pairs")
    parser.add_argument("-n", type=int, default=100000, help="number of configurations (default 100000)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--chunk-size", type=int, default=5000)
    parser.add_argument("--scheduler", help="address of a running Dask scheduler, e.g. tcp://10.0.0.5:8786")
    parser.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes (default 2)")
    parser.add_argument("--check", action="store_true",
                        help="also label in this process on one thread and require equal labels")
    parser.add_argument("--output", help="write the labels here (.npy)")
    args = parser.parse_args()

    from dask.distributed import Client, LocalCluster

    robot = load_robot(args.urdf, args.srdf)
    configurations = robot.random_configurations(args.n, args.seed)
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=None)
        client = Client(cluster)
    with client:
        label(client, args.urdf, args.srdf, configurations[: args.chunk_size])  # workers load the robot
        start = time.perf_counter()
        labels = label(client, args.urdf, args.srdf, configurations, args.chunk_size)
        seconds = time.perf_counter() - start
    print(f"{robot.name}: {args.n} configurations, {int(labels.sum())} colliding, {seconds:.3f} s on Dask "
          f"({args.n / seconds:.0f} configurations/s)")
    if args.check:
        start = time.perf_counter()
        reference = robot.check_batch(configurations, num_threads=1)["colliding"]
        single = time.perf_counter() - start
        same = np.array_equal(labels, reference)
        print(f"one thread in this process: {single:.3f} s ({args.n / single:.0f} configurations/s); "
              f"labels {'equal' if same else 'DIFFER'}")
        if not same:
            raise SystemExit(1)
    if args.output:
        np.save(args.output, labels)


if __name__ == "__main__":
    main()
