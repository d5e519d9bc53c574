"""Run a dataset: one job on every object of a set, resumable, on any executor.

The driver: it expands the inputs, checks the results folder's job, skips
the objects whose records stand, computes the rest (in this process, on a
local pool, or on any ``concurrent.futures.Executor``), writes each record as
it arrives and the tables at the end, interrupted or not.
"""

from __future__ import annotations

import json
import os
import sys
import time
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, Future, as_completed
from contextlib import suppress
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

from ..errors import InputError, printable
from ..extras import require
from ..files.outdir import locked, remove_temporaries, write_atomically
from ..files.saves import holding
from .inputs import expand_inputs, fingerprint, record_name
from .job import Job, LabelJob
from .one_object import failed_record, process_object
from .pool import Pending, local_pool, object_dims
from .progress import ProgressLines, bar_size, every_from_environment
from .records import STATUSES, check_job, held_records, write_table
from .workers import tell_dask_run

__all__ = ["SYNTHESIS", "Summary", "run_dataset"]

#: The default job: the best grasps of the fewest fingers that hold each object.
SYNTHESIS = Job()


@dataclass(frozen=True)
class Summary:
    """What a run did.

    Attributes
    ----------
    objects : int
        Objects in the input set.
    done, failed, timeout : int
        Objects with each status in ``DIR`` after the run.
    computed : int
        Objects computed by this run (the others were skipped: done before).
    skipped : int
    seconds : float
        Wall time of this run.
    workers : int
    out : Path
    interrupted : bool
    incomplete : int
        Synthesis: objects done whose search left sites undecided (``undecided`` above 0
        in their records, ``complete`` false): grasps may be missing there.
    """

    objects: int
    done: int
    failed: int
    timeout: int
    computed: int
    skipped: int
    seconds: float
    workers: int
    out: Path
    interrupted: bool = False
    incomplete: int = 0

    @property
    def throughput(self) -> float:
        """Objects computed per second of this run."""
        return self.computed / self.seconds if self.seconds > 0 else 0.0

    def to_dict(self) -> dict[str, Any]:
        return {**{f.name: getattr(self, f.name) for f in fields(self)},
                "out": str(self.out), "objects_per_second": round(self.throughput, 4)}

    def __str__(self) -> str:
        lines = [f"{self.objects} objects: {self.done} done, {self.failed} failed, "
                 f"{self.timeout} over the time limit; {self.skipped} skipped (done before)"]
        if self.computed:
            lines.append(f"computed {self.computed} in {self.seconds:.1f} s "
                         f"({self.throughput:.3g} objects/s on {self.workers} "
                         f"worker{'s' if self.workers != 1 else ''})")
        if self.incomplete:
            lines.append(f"not complete: {self.incomplete} object"
                         f"{'s' if self.incomplete != 1 else ''} with sites undecided (grasps "
                         "may be missing there; the table's complete and undecided columns)")
        lines.append(f"results: {self.out / 'results.parquet'} (one row per object), "
                     f"{self.out / 'objects'} (full records)")
        if self.interrupted:
            lines.append("interrupted: run the same command again to resume")
        return "\n".join(lines)


class _OutputFailed(Exception):
    """Writing to ``DIR`` failed (a full disk, say): the run stops."""


def run_dataset(inputs: Sequence[str | Path], out: str | Path, job: Job | LabelJob = SYNTHESIS, *,
                executor: Executor | None = None, workers: int | None = None,
                retry_failed: bool = False, progress: bool | None = None,
                log: Callable[[str], object] | None = None,
                progress_every: float | None = None) -> Summary:
    """Run ``job`` on every object of ``inputs``, writing results to ``out``; resumable.

    Parameters
    ----------
    inputs : sequence of str or Path
        Files, folders and glob patterns (:func:`expand_inputs`).
    out : str or Path
        The results folder (created). Re-running with the same job resumes.
        Locked while the run lasts: a second run on it is refused.
    job : Job or forceclosure.datasets.gripper_job.GripperJob
        Regions (synthesis, analysis) or labelled parallel-jaw grasps.
    executor : concurrent.futures.Executor, optional
        Where the objects are computed, e.g. a Dask ``Client.get_executor()``.
        Its workers must see the input files at the same paths. Default: a
        local process pool of ``workers`` processes (all cores); with
        ``workers=1`` and no time limit everything runs in this process.
    retry_failed : bool
        Compute failed and timed-out objects again.
    progress : bool, optional
        True: a progress bar; False: no progress; default: a bar when
        standard error is a terminal, else a progress line
        (:class:`forceclosure.datasets.progress.ProgressLines`: done/total, rate,
        time left) every ``progress_every`` seconds.
    log : callable, optional
        Called with a line per failure or warning, per worker compiling the
        kernels, and the progress lines (default: written above the progress
        bar, on standard error).
    progress_every : float, optional
        Seconds between progress lines (0: one per object; default:
        ``FORCECLOSURE_PROGRESS_SECONDS``, else 10).

    Returns
    -------
    Summary

    Raises
    ------
    InputError
        Bad options, ``out`` in use by another run or holding another job's
        results, or ``out`` not writable (a full disk: the records written
        so far are kept).

    Examples
    --------
    >>> import tempfile
    >>> out = tempfile.mkdtemp()
    >>> s = run_dataset(["cube", "l-prism"], out, Job(contact="soft", mu=0.5, top=1), workers=1,
    ...                 progress=False)
    >>> s.done, s.computed
    (2, 2)
    >>> run_dataset(["cube", "l-prism"], out, Job(contact="soft", mu=0.5, top=1), workers=1,
    ...             progress=False).skipped
    2
    """
    require("pyarrow.parquet", "the dataset's table", "table")  # refused before any work
    # never its own job.json, records, tables, pictures and exports
    paths = expand_inputs(inputs, exclude=out, folders=getattr(job, "output_folders", list)())
    if job.mode == "synthesize":  # a hand no object can serve: refuse before any work
        from ..synthesis.best import check_hand

        for dim in object_dims(paths):
            check_hand(dim, job.fingers, job.contact, job.mu, top=job.top,
                       construction=job.construction, method=job.method)
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out}: is a file, not a folder")
    folder = out / "objects"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise InputError(f"--out {out}: cannot create it ({e.strerror})") from None
    with locked(out):
        remove_temporaries([out, folder])
        try:
            check_job(out, job, log)
        except OSError as e:
            raise InputError(f"--out {out}: cannot write job.json ({e.strerror})") from None
        return _run_locked(paths, out, job, executor, workers, retry_failed, progress, log,
                           progress_every)


def _terminal() -> bool:
    """Whether standard error is a terminal (a progress bar's place)."""
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def _run_locked(paths: list[Path], out: Path, job: Job | LabelJob, executor: Executor | None,
                workers: int | None, retry_failed: bool, progress: bool | None,
                log: Callable[[str], object] | None,
                progress_every: float | None = None) -> Summary:
    from tqdm import tqdm

    folder = out / "objects"
    names = {record_name(p): p for p in paths}
    every = every_from_environment() if progress_every is None else float(progress_every)
    if not every >= 0:
        raise InputError(f"progress_every must be a number of seconds >= 0, got {every!r}")
    lines_wanted = progress is None and not _terminal()   # piped: lines instead of a bar
    size = bar_size()  # none: the terminal's own, followed as it changes
    bar = tqdm(total=0, unit="obj", desc="objects", file=sys.stderr,
               disable=not progress if progress is not None else None,
               dynamic_ncols=not size, **size)
    write = log or (lambda line: bar.write(line, file=sys.stderr))

    def say(line: str) -> None:
        write(printable(line))
    identity = job.identity()
    stamps = {n: fingerprint(p, job) for n, p in names.items()}
    held = held_records(folder, names, identity, stamps, say, getattr(job, "check", None), job)
    keep = {"done"} if retry_failed else set(STATUSES)
    run = Pending({n: p for n, p in names.items()
                if n not in held or held[n].get("status") not in keep})
    skipped = len(names) - len(run.todo)
    records = {n: held[n] for n in names if n in held}
    workers = workers or os.cpu_count() or 1
    start = time.perf_counter()
    computed, interrupted = 0, False
    failure: OSError | None = None
    bar.reset(total=len(run.todo))
    ticker = ProgressLines(len(run.todo), say, every=every) if lines_wanted else None

    def finish(name: str, record: dict[str, Any]) -> None:
        nonlocal computed
        record = {**record, "job": identity, "input": stamps[name]}
        try:
            if hasattr(job, "store"):  # files beside the record (gripper: labels), first
                record = job.store(folder, name, record)
            write_atomically(folder / name, json.dumps(record) + "\n")
        except OSError as e:
            raise _OutputFailed(e) from e
        records[name] = record
        run.todo.pop(name, None)
        computed += 1
        bar.update(1)
        if ticker is not None:
            ticker.update(1)
        if record["status"] != "done":
            say(f"forceclosure: {record['status']}: {record['error']}")

    table: OSError | None = None
    try:
        if executor is None and workers == 1 and job.timeout is None:
            from ..kernels import on_compiling

            before = on_compiling(say)  # this process compiles: said above the bar
            try:
                for name, path in list(run.todo.items()):
                    finish(name, process_object(path, job))
            finally:
                on_compiling(before)
        elif executor is None:
            local_pool(workers, run, job, finish, say)
        else:
            _drain(executor, run, job, finish, say)
    except KeyboardInterrupt:
        interrupted = True
    except _OutputFailed as e:
        failure = e.args[0]
    finally:
        bar.close()
        try:
            with holding():  # Ctrl-C on the command line waits for the tables (app/interrupt)
                write_table(out, records.values())
                if hasattr(job, "write_tables"):  # tables of its own (gripper: grasps.parquet)
                    job.write_tables(out, records.values())
        except OSError as e:
            table = e
    error = failure or table
    if error is not None:
        kept = (f"the {len(records)} records written are kept"
                + ("" if table is None else "; results.parquet is not updated"))
        raise InputError(f"--out {out}: cannot write ({error.strerror or error}): {kept}; "
                         "make room and run the same command again to resume")
    statuses = [r.get("status") for r in records.values()]
    return Summary(objects=len(names), done=statuses.count("done"),
                   failed=statuses.count("failed"), timeout=statuses.count("timeout"),
                   computed=computed, skipped=skipped,
                   seconds=time.perf_counter() - start, workers=workers, out=out,
                   interrupted=interrupted,
                   incomplete=sum(r.get("status") == "done"
                                  and isinstance(r.get("undecided"), int) and r["undecided"] > 0
                                  for r in records.values()))


def _on_executor(path: Path, job: Job | LabelJob) -> dict[str, Any]:
    """:func:`process_object` on an executor's worker; a Dask worker first arranges to tell
    the run when it compiles the kernels (:func:`forceclosure.datasets.workers.tell_dask_run`)."""
    tell_dask_run()
    return process_object(path, job)


def _drain(executor: Executor, run: Pending, job: Job | LabelJob,
           finish: Callable[[str, dict[str, Any]], None],
           say: Callable[[str], object] | None = None) -> None:
    """Submit every pending object to ``executor`` and finish each as its result arrives.

    An object whose future fails (Dask's KilledWorker, after the scheduler's
    own retries) is recorded as failed. On a Dask executor, what its workers
    tell the run (compiling the kernels) is said with ``say``.
    """
    client = getattr(executor, "_client", None)  # Dask's Client.get_executor()
    if say is None or client is None or not callable(getattr(client, "subscribe_topic", None)):
        _drain_futures(executor, run, job, finish)  # nothing to listen to, or no one to tell
        return
    from .workers import TOPIC

    with suppress(Exception):
        client.subscribe_topic(TOPIC, lambda event: say(str(event[1])))
    try:
        _drain_futures(executor, run, job, finish)
    finally:
        with suppress(Exception):
            client.unsubscribe_topic(TOPIC)


def _drain_futures(executor: Executor, run: Pending, job: Job | LabelJob,
                   finish: Callable[[str, dict[str, Any]], None]) -> None:
    futures: dict[Future, str] = {executor.submit(_on_executor, run.todo[n], job): n
                                  for n in run.todo}
    for future in as_completed(futures):
        name = futures[future]
        try:
            record = future.result()
        except Exception as e:  # the executor lost the object (e.g. KilledWorker)
            why = str(e).splitlines()[0] if str(e) else ""
            finish(name, failed_record(run.todo[name], f"{run.todo[name].name}: its worker died "
                                                 f"({type(e).__name__}: {why})"))
            continue
        finish(name, record)
