"""A fleet of ambient records analysed on Dask: the same `msd.oma` call on every record,
spread over a local cluster's workers (or any Dask cluster), the results gathered in the
records' order — the same numbers as the serial loop, since each record's analysis is
deterministic and independent.

    pip install ./crates/msd-py "dask[distributed]" scipy && python examples/python/oma_fleet_dask.py

The records here are a five-storey building's accelerations simulated with scipy (one
per "hour", the second storey stiffening by 0.5 % an hour, as a temperature change would
do); with real files, read each one inside the task instead of shipping the arrays.
"""
import numpy as np
from dask.distributed import Client, LocalCluster
from scipy import linalg, signal

import msd


def hourly_record(hour, fs=100.0, n=20_000):
    """Accelerations of a shear building under white forces, scipy's ZOH simulation."""
    k = 10_000.0 * np.ones(5)
    k[1] *= 1 + 0.005 * hour
    K = np.diag(k + np.append(k[1:], 0.0)) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
    M = 25.91 * np.eye(5)
    w2, phi = linalg.eigh(K, M)
    C = M @ phi @ np.diag(0.04 * np.sqrt(w2)) @ phi.T @ M
    Mi = np.linalg.inv(M)
    A = np.block([[np.zeros((5, 5)), np.eye(5)], [-Mi @ K, -Mi @ C]])
    B = np.vstack([np.zeros((5, 5)), Mi])
    system = signal.cont2discrete((A, B, np.hstack([-Mi @ K, -Mi @ C]), Mi), 1 / fs)
    rng = np.random.default_rng(hour)
    _, y, _ = signal.dlsim(system[:4] + (1 / fs,), rng.normal(size=(n, 5)))
    return y + 0.1 * y.std(axis=0) * rng.normal(size=y.shape)


def analyse(hour):
    """One record's modes: (fn [Hz], its 95 % interval) of each."""
    fit = msd.oma(hourly_record(hour), 100.0)
    return [(m.natural_frequency_hz.value, tuple(m.natural_frequency_hz.ci95)) for m in fit.modes]


if __name__ == "__main__":
    hours = range(6)
    with LocalCluster(n_workers=2, threads_per_worker=1) as cluster, Client(cluster) as client:
        tracked = client.gather(client.map(analyse, hours))
    for hour, modes in zip(hours, tracked):
        print(f"hour {hour}: " + ", ".join(f"{f:.4f} Hz" for f, _ in modes))
    assert tracked == [analyse(h) for h in hours], "the cluster and the serial loop differ"
    print("the cluster's results equal the serial loop's")
