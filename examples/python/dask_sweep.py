"""A (γ, δ) map on a Dask LocalCluster: the grid's points are cut into chunks, each chunk is one
`hdgear.sweep` call on a worker, and the result must equal a single `hdgear.sweep` call.

    python examples/python/dask_sweep.py [N_GAMMA N_DELTA]
"""
import sys
import time

import numpy as np
from dask.distributed import Client, LocalCluster

import hdgear

ng, nd = (int(sys.argv[1]), int(sys.argv[2])) if len(sys.argv) > 2 else (40, 10)
gammas = np.geomspace(0.05, 30, ng)
deltas = np.linspace(8, 16, nd)
# every point of the grid, γ fastest (the order of hdgear.sweep's grid)
G = np.tile(gammas, nd)
D = np.repeat(deltas, ng)


def chunk(lo, hi):
    return hdgear.sweep({"gamma": G[lo:hi], "delta": D[lo:hi]}, grid=False, threads=1)


if __name__ == "__main__":
    t0 = time.perf_counter()
    single = hdgear.sweep({"gamma": gammas, "delta": deltas})
    t_single = time.perf_counter() - t0
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        t0 = time.perf_counter()
        bounds = list(range(0, len(G), 50)) + [len(G)]
        futures = [client.submit(chunk, lo, hi) for lo, hi in zip(bounds, bounds[1:])]
        parts = client.gather(futures)
        t_dask = time.perf_counter() - t0
    try:
        import pandas as pd
        merged = pd.concat(parts, ignore_index=True)
        merged["index"] = np.arange(len(merged))
        pd.testing.assert_frame_equal(merged, single)
    except ImportError:
        for k in single:
            a = np.concatenate([p[k] for p in parts])
            if k == "index":
                a = np.arange(len(a))
            assert all((x == y) or (x != x and y != y) for x, y in zip(a, single[k])), k
    print(f"{len(G)} points: one hdgear.sweep call {t_single:.2f} s; {len(parts)} chunks on a Dask "
          f"LocalCluster (2 workers) {t_dask:.2f} s; identical results")
