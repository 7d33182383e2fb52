"""Run a deterministic function over a list of inputs, in parallel processes (concurrent.futures) with a
progress bar (tqdm), or on an existing Dask distributed cluster (`scheduler` = its address). Each input's
result is a pure function of it, so both give identical results, in the order of the inputs. Given each
input's expected cost, the dearest go first (longest processing time first): a long run started last would
leave the other cores idle at the end (the serial tail)."""
from concurrent.futures import ProcessPoolExecutor, as_completed
import os


def run_all(function, items, workers=None, scheduler=None, progress=True, desc="runs", unit="run", cost=None):
    """[function(item) for item in items], computed in parallel (a module-level function, or a
    functools.partial of one, so that processes and Dask workers can run it); `cost`: each item's expected
    cost (any unit), the dearest submitted first."""
    items = list(items)
    if not items:
        raise ValueError("nothing to run: the list of inputs is empty")
    order = list(range(len(items)))
    if cost is not None:
        cost = list(cost)
        if len(cost) != len(items):
            raise ValueError(f"{len(cost)} costs given for {len(items)} inputs: give one per input")
        order.sort(key=lambda i: -cost[i])      # stable: equal costs keep their order
    bar = None
    if progress:
        from tqdm import tqdm
        bar = tqdm(total=len(items), desc=desc, unit=unit)
    results = [None] * len(items)
    if scheduler:
        from dask.distributed import Client, as_completed as dask_completed
        with Client(scheduler) as client:
            futures = client.map(function, [items[i] for i in order], pure=True)   # equal items share one future
            for _ in dask_completed(futures):
                if bar:
                    bar.update()
            for i, f in zip(order, futures):
                results[i] = f.result()
    else:
        with ProcessPoolExecutor(max_workers=workers or min(len(items), os.cpu_count() or 1)) as pool:
            futures = {pool.submit(function, items[i]): i for i in order}
            for f in as_completed(futures):
                results[futures[f]] = f.result()
                if bar:
                    bar.update()
    if bar:
        bar.close()
    return results
