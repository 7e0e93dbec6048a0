"""The Dask example on a LocalCluster (2 workers, threads, in-process transport) gives the single-threaded labels."""
import numpy as np
import pytest

import fcl_rs

distributed = pytest.importorskip("dask.distributed")
import label_configurations  # noqa: E402  (python/examples, put on sys.path by conftest)


def test_local_cluster_labels_equal_one_thread(chain_urdf):
    robot = fcl_rs.Robot(chain_urdf)
    q = robot.random_configurations(3000, seed=3)
    reference = robot.check_batch(q, num_threads=1)["colliding"]
    assert 100 < reference.sum() < 2900
    # Threads in this process: in-process transport, no network (a real cluster is the same client code).
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        labels = label_configurations.label(client, chain_urdf, "", q, chunk_size=500)
    assert labels.dtype == np.bool_ and np.array_equal(labels, reference)
