"""Where a sweep's runs and a tune's trials execute beside this process: Ray tasks (on a local
cluster, or an existing one at ``address``) and local worker processes.

**A sweep over Ray** (:func:`run_ray`): each run folder travels with its task. The driver
packs the prepared folder; the task unpacks it in a temporary folder on whichever node runs
it, runs it there with the one CPU it holds, and returns the finished folder packed; the
driver puts it in place of the prepared one (:func:`place`), under the folder's lock, the files
first and ``result.json`` last, so an interrupted return leaves the folder as it was
prepared, to run again with ``animat run --resume``. The nodes therefore need no shared file
system. What comes back is read as untrusted data (:mod:`.launch.archive`: regular files and
folders only, each member checked before anything is written), and a run folder holds no code. The
tasks are spread over the nodes (Ray's ``SPREAD``); a task Ray loses (a node gone) leaves its
folder as prepared and its row ``failed``.

**A tune's workers** (:func:`run_workers`): ``workers`` processes here, or as many Ray tasks,
each running :func:`animat.experiments.tune.work` on the one study, so the sampler and the
pruner see every worker's trials. The study's storage must be one every worker reaches: the
journal file in OUT (one machine, or a shared file system) or an RDB URL (``--storage``); a
trial's folder is written under OUT where its worker runs.

Each task and worker process imports the modules this one imported by ``animat --import``
first (:func:`~animat.experiments.launch.plugins.with_imports`), so it knows the same
registrations.
"""

from __future__ import annotations

import multiprocessing
import os
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from .launch.archive import pack, place, unpack
from .launch.execute import execute
from .launch.folders import read_status
from .launch.lock import RunError
from .launch.machine import available_cpus
from .launch.plugins import imported, with_imports


def _run_packed(name: str, data: bytes) -> tuple[bytes, str]:
    """A Ray task's body: run the packed folder ``name`` in a temporary folder on this node;
    returns it packed, finished (or failed, as its result.json says), and the node's id."""
    import ray

    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(os.path.realpath(scratch)) / name
        unpack(data, folder)
        try:
            execute(folder, threads=1)  # the one CPU the task holds
        except Exception:  # recorded in the folder's result.json
            pass
        return pack(folder), ray.get_runtime_context().get_node_id()


def _ray(address: str | None, num_cpus: int | None):
    """Ray, connected (a local cluster when ``address`` is None); and whether this call
    started the connection (so it shuts it down)."""
    try:
        import ray
    except ImportError:
        raise RunError("the ray executor needs Ray: pip install 'artificial-animals[ray]'"
                       ) from None
    started = not ray.is_initialized()
    if started:
        ray.init(address=address or "local", num_cpus=None if address else num_cpus,
                 include_dashboard=False, log_to_driver=False)  # "local": a new one here
    return ray, started


def run_ray(folders: list[Path], address: str | None = None, num_cpus: int | None = None
            ) -> list[dict]:
    """Execute each prepared folder as a Ray task of one CPU, spread over the cluster's
    nodes, each folder returned to this driver (see the module's docstring); per folder its
    status, with ``node``, the Ray node that ran it."""
    ray, started = _ray(address, num_cpus)
    task = ray.remote(num_cpus=1, scheduling_strategy="SPREAD", max_retries=0)(with_imports)
    try:
        refs = [task.remote(imported(), _run_packed, folder.name, pack(folder))
                for folder in folders]
        results = []
        for folder, ref in zip(folders, refs):
            try:
                data, node = ray.get(ref)
            except ray.exceptions.RayError as error:  # lost with its node: left as prepared
                results.append({**read_status(folder), "status": "failed",
                                "error": f"ray: {str(error).splitlines()[0]}"})
                continue
            results.append({**place(data, folder), "node": node})
        return results
    finally:
        if started:
            ray.shutdown()


def run_workers(worker, workers: int, executor: str, address: str | None, *args) -> None:
    """``workers`` calls of ``worker(threads, *args)`` at once (a module-level function, e.g.
    :func:`animat.experiments.tune.worker`): processes here sharing the CPUs out, or Ray tasks
    of one CPU each; an error in a worker is raised here once all have ended."""
    if executor == "ray":
        ray, started = _ray(address, None)
        try:
            task = ray.remote(num_cpus=1, max_retries=0)(with_imports)
            ray.get([task.remote(imported(), worker, 1, *args) for _ in range(workers)])
        finally:
            if started:
                ray.shutdown()
        return
    threads = max(1, available_cpus() // workers)
    context = multiprocessing.get_context("spawn")  # no forked Numba or Optuna state
    with ProcessPoolExecutor(max_workers=workers, mp_context=context) as pool:
        futures = [pool.submit(with_imports, imported(), worker, threads, *args)
                   for _ in range(workers)]
        for future in futures:
            future.result()
