"""The dask backend's failures are one line each: addresses, clusters that fail, scratch files."""

from __future__ import annotations

import os
import signal
import threading
import time
import warnings
from concurrent.futures import CancelledError

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.ensemble import dask_backend, run_ensemble
from lagrangian.errors import ModelError
from lagrangian.numeric import compile_equations

pytest.importorskip("distributed")


@pytest.fixture
def unused_port():
    """A loopback port that nothing listens on (bound, then released)."""
    import socket

    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.fixture(scope="module")
def pendulum():
    return compile_equations(lg.load("simple_pendulum").equations_of_motion())


@pytest.mark.parametrize(
    "address",
    ["foo", "127.0.0.1:8786", "tcp://127.0.0.1", "tcp://127.0.0.1:0", "tcp://127.0.0.1:99999",
     "tcp://[::1", "inproc://x", "ucx://127.0.0.1:1", "tcp://a b:1", "tcp://x:1/path"],
)  # fmt: skip
def test_a_malformed_scheduler_address_is_refused_before_anything_runs(address):
    with pytest.raises(ModelError, match=r"^the dask scheduler address must be tcp://HOST:PORT"):
        dask_backend.check_scheduler(address)


def test_a_well_formed_address_gives_host_and_port():
    assert dask_backend.check_scheduler("tcp://127.0.0.1:8786") == ("127.0.0.1", 8786)
    assert dask_backend.check_scheduler("tls://[::1]:8786") == ("::1", 8786)


def test_a_refused_port_fails_at_once(pendulum, unused_port):
    with pytest.raises(dask_backend.ClusterError, match=r"^cannot reach the dask scheduler "):
        run_ensemble(
            pendulum, initial={"theta": [0.1, 0.2]}, t_end=0.1, dt=0.01, backend="dask",
            scheduler=f"tcp://127.0.0.1:{unused_port}",
        )  # fmt: skip


def test_a_scheduler_needs_backend_dask(pendulum):
    with pytest.raises(ModelError, match=r"^a dask scheduler needs backend dask \(not numpy\)$"):
        run_ensemble(
            pendulum, initial={"theta": [0.1]}, t_end=0.1, scheduler="tcp://127.0.0.1:8786"
        )


class _FakeDistributed:
    """A ``distributed`` whose cluster fails as asked: at start, or by killing the workers."""

    class KilledWorker(Exception):
        pass

    def __init__(self, fail_at: str):
        self.fail_at = fail_at
        self.closed: list[str] = []

    def LocalCluster(self, **options):
        if self.fail_at == "start":
            raise RuntimeError("Nanny failed to start.\nmore lines")
        return _Closing(self, "cluster")

    def Client(self, *args, **options):
        return _FakeClient(self)

    def as_completed(self, futures):
        return iter(futures)  # nothing is added: the first task's result already fails


class _Closing:
    def __init__(self, fake, name):
        self.fake, self.name = fake, name

    def close(self):
        self.fake.closed.append(self.name)


class _FakeClient(_Closing):
    def __init__(self, fake):
        super().__init__(fake, "client")

    def nthreads(self):
        return {"worker": 2}

    def scheduler_info(self):
        return {"workers": {"tcp://127.0.0.1:1": {}}}

    def submit(self, *args, **options):
        return _Killed(self.fake)


class _Killed:
    def __init__(self, fake):
        self.fake = fake

    def result(self):
        if self.fake.fail_at == "cancel":  # what a task whose input was lost for good raises
            raise CancelledError("_task-1 cancelled for reason: already forgotten.")
        raise self.fake.KilledWorker("Attempted to run task _task on 4 different workers")


@pytest.mark.parametrize(
    ("fail_at", "message", "closed"),
    [
        ("start", r"^the local dask cluster did not start: Nanny failed to start\.$", []),
        ("run", r"^the dask cluster failed during the run: Attempted", ["client", "cluster"]),
        (
            "cancel",
            r"^the dask cluster failed during the run: _task-1 cancelled for reason: already "
            r"forgotten\.$",
            ["client", "cluster"],
        ),
    ],
)  # fmt: skip
def test_a_failing_cluster_is_one_line(pendulum, monkeypatch, fail_at, message, closed):
    fake = _FakeDistributed(fail_at)
    cloudpickle = pytest.importorskip("cloudpickle")
    monkeypatch.setattr(dask_backend, "_distributed", lambda: (fake, cloudpickle))
    with pytest.raises(dask_backend.ClusterError, match=message):
        run_ensemble(pendulum, initial={"theta": [0.1, 0.2]}, t_end=0.1, dt=0.01, backend="dask")
    assert fake.closed == closed


@pytest.mark.slow
def test_the_local_cluster_leaves_no_scratch_folder(pendulum, tmp_path, monkeypatch):
    import tempfile

    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr(tempfile, "tempdir", None)  # read TMPDIR again
    result = run_ensemble(
        pendulum, initial={"theta": np.array([0.1, 0.2])}, t_end=0.1, dt=0.01, backend="dask"
    )
    assert result.shape == (2,)
    assert list(tmp_path.iterdir()) == []


def _kill_workers_while_they_work(client, started: threading.Event) -> int:
    """SIGKILL every worker process once tasks run on them (their nannies start new ones);
    the number killed.  Bounded: the run under test is watched by its thread's join."""
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not any(client.processing().values()):
        time.sleep(0.05)
    started.set()
    pids = client.run(os.getpid)
    for pid in pids.values():
        os.kill(pid, signal.SIGKILL)
    return len(pids)


@pytest.mark.slow
def test_workers_killed_during_the_run_are_replaced_and_said(pendulum):
    # was: the model's scattered payload died with the workers, every task waiting on it was
    # cancelled, and the run ended in "internal error: FutureCancelledError" (exit 1) after
    # distributed's log lines; now the payload is computed again and the chunks re-run
    distributed = pytest.importorskip("distributed")
    thetas = np.linspace(0.1, 1.0, 24)
    expected = run_ensemble(pendulum, initial={"theta": thetas}, t_end=2.0, dt=0.01)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
        dashboard_address=None,
    ) as cluster, distributed.Client(cluster) as client:  # fmt: skip
        outcome: dict = {}

        def run():
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    outcome["result"] = run_ensemble(
                        pendulum, initial={"theta": thetas}, t_end=2.0, dt=0.01,
                        backend="dask", scheduler=cluster.scheduler_address, chunk_size=2,
                    )  # fmt: skip
                except Exception as error:  # reported by the assertion below
                    outcome["error"] = error
            outcome["warnings"] = [str(w.message) for w in caught]

        worker = threading.Thread(target=run)
        worker.start()
        started = threading.Event()
        killed = _kill_workers_while_they_work(client, started)
        worker.join(timeout=300)
        assert not worker.is_alive(), "the run did not end within 300 s of the kill"
    assert killed == 2
    assert "error" not in outcome, outcome.get("error")
    for name, values in expected.final_state.items():  # the same chunks, the same numbers
        np.testing.assert_allclose(outcome["result"].final_state[name], values, rtol=0, atol=0)
    assert (
        "2 dask workers left the cluster during the run (killed or restarted); their chunks "
        "ran again on the workers there"
    ) in outcome["warnings"]
