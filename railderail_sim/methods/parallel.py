"""Run a deterministic function over a list of inputs, in parallel processes (concurrent.futures) with a
progress bar (tqdm), or on an existing Dask distributed cluster (`scheduler` = its address). Each input's
result is a pure function of it, so both give identical results, in the order of the inputs; nothing here
schedules work itself."""
from concurrent.futures import ProcessPoolExecutor, as_completed
import os


def run_all(function, items, workers=None, scheduler=None, progress=True, desc="runs", unit="run"):
    """[function(item) for item in items], computed in parallel (a module-level function, or a
    functools.partial of one, so that processes and Dask workers can run it)."""
    items = list(items)
    if not items:
        raise ValueError("nothing to run: the list of inputs is empty")
    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=len(items), desc=desc, unit=unit)
    results = [None] * len(items)
    if scheduler:
        from dask.distributed import Client, as_completed as dask_completed
        with Client(scheduler) as client:
            futures = client.map(function, items, pure=True)   # equal items share one future
            for _ in dask_completed(futures):
                if bar:
                    bar.update()
            results = [f.result() for f in futures]
    else:
        with ProcessPoolExecutor(max_workers=workers or min(len(items), os.cpu_count() or 1)) as pool:
            futures = {pool.submit(function, item): i for i, item in enumerate(items)}
            for f in as_completed(futures):
                results[futures[f]] = f.result()
                if bar:
                    bar.update()
    if bar:
        bar.close()
    return results
