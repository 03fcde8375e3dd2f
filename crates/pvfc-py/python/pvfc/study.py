"""Studies: ``pvfc.sweep`` runs a :class:`pvfc.Study` here or on a Dask cluster into a pandas
DataFrame (one row per run: its index, the values of its axes, its metrics, its error)."""

from __future__ import annotations

import os
from typing import Any, List, Optional, Sequence, Tuple, Union

from ._pvfc import Study

Row = Tuple[int, List[float], List[Optional[float]], Optional[str]]


def _run_batch(study: Study, indices: Sequence[int]) -> List[Row]:
    """Runs a batch of a study's runs on one worker (one thread: the cluster is the
    parallelism)."""
    return study.run(list(indices), threads=1)


def _frame(study: Study, rows: Sequence[Row]) -> Any:
    import pandas as pd  # type: ignore[import-untyped,unused-ignore]

    rows = sorted(rows, key=lambda r: r[0])
    columns = study.columns
    records = [(i, *params, *metrics) for i, params, metrics, _ in rows]
    df = pd.DataFrame.from_records(records, columns=columns[:-1])
    df = df.astype({name: "float64" for name in columns[1:-1]})
    # An object column: None where the run did not fail.
    df["error"] = pd.Series([r[3] for r in rows], dtype="object")
    return df


def sweep(
    study: Union[Study, str, "os.PathLike[str]"],
    client: Any = None,
    *,
    threads: Optional[int] = None,
    batch_size: Optional[int] = None,
    retries: int = 3,
) -> Any:
    """Runs every run of ``study`` (a :class:`pvfc.Study` or the path of its TOML file) and
    returns a pandas DataFrame with one row per run, by index: ``run``, the axes' keys, the
    metrics (NaN where a metric does not apply or the run failed) and ``error`` (``None``
    unless the run failed).

    Without ``client`` the runs go to this machine's cores (``threads``, default all), in
    Rust with the GIL released. With a ``dask.distributed.Client`` they go to its workers in
    batches of ``batch_size`` runs (default: about four batches per worker thread); a batch
    whose worker dies is run again (up to ``retries`` times). The numbers are the same, bit
    for bit, either way.
    """
    if not isinstance(study, Study):
        study = Study.from_file(os.fspath(study))
    if client is None:
        return _frame(study, study.run(None, threads=threads))
    n = len(study)
    if batch_size is None:
        workers = sum(client.nthreads().values()) or 1
        batch_size = max(1, -(-n // (4 * workers)))
    if batch_size < 1:
        raise ValueError(f"batch_size: {batch_size}, must be ≥ 1")
    batches = [list(range(i, min(i + batch_size, n))) for i in range(0, n, batch_size)]
    # The study goes to the cluster once; every batch refers to it.
    [shared] = client.scatter([study], broadcast=True)
    futures = client.map(_run_batch, [shared] * len(batches), batches, retries=retries, pure=False)
    rows: List[Row] = [row for batch in client.gather(futures) for row in batch]
    return _frame(study, rows)
