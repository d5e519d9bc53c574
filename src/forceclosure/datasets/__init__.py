"""Datasets: one job over thousands of objects, resumable, on any executor.

``forceclosure dataset INPUT... --out DIR`` (and :func:`run_dataset`) runs
one job on every object of a set: the synthesis of ``forceclosure
synthesize`` (the best grasps and their independent regions, §5), or the
analysis of grasps given per object (Theorem 1, with epsilon and a check
that the contacts lie on the object). The objects are spread over an
executor: a local process pool over all cores by default, or any
``concurrent.futures.Executor``, a Dask cluster's included
(``Client.get_executor()``).

Nothing is lost and nothing is done twice. ``DIR`` holds

* ``job.json``: the job; re-running in the same ``DIR`` must ask for the
  same job, and then resumes;
* ``objects/<name>-<hash>.json``: one record per object, written
  atomically (a temporary file in the same folder, synced, then renamed)
  by the driver as soon as the object finishes, whatever worker computed
  it. Each record carries the job's identity (the options that change
  results) and its input's fingerprint (a SHA-256 of the object file, of
  the meshes a URDF names and, in analysis, of the grasp file). Objects
  with a record are skipped on a re-run (failed ones too, unless
  ``retry_failed``); a record that is damaged (not JSON, not a record,
  fields missing or of the wrong type), foreign (copied from another
  object's) or stale (another job's, or its input changed since) is
  computed again, with a warning;
* ``.lock``: held (``flock``) by the run writing to ``DIR``; a second run
  on the same ``DIR`` is refused in one line while the first is alive (the
  kernel drops the lock when its holder dies, however it dies);
* ``results.parquet``: one row per object (status, timings, best grasps
  and region sizes), rebuilt from the records at the end of every run,
  also an interrupted one.

A bad or unreadable object is recorded as ``failed`` with its one-line
error; an object over the time limit as ``timeout``. On the local pool
(pebble's ``ProcessPool``) each object runs in a worker process that can
be killed, so the time limit holds inside compiled code too: the worker is
asked to stop at the limit (``SIGALRM``, between bytecodes) and killed
:data:`HARD_GRACE` seconds later if it has not. A worker that dies
(killed, out of memory) costs only the object it was running, which is run
again on a fresh worker; an object that kills workers :data:`MAX_CRASHES`
times is recorded as ``failed``. A watchdog kills a worker stopped
(``SIGSTOP``) for :data:`STALL_SECONDS`, and its object is run again.
Workers die with the run (Linux: ``PR_SET_PDEATHSIG``), so a killed run
leaves no computation behind. ``workers=1`` without a time limit runs in
this process. On Dask the scheduler retries objects whose worker died,
and the time limit is raised between bytecodes only (a Dask worker's
thread cannot be killed).

A full disk (any error writing to ``DIR``) stops the run with one line:
the records written so far are kept, the temporary files removed, and the
same command resumes once there is room.

The package, one concern a module, data flowing one way: :mod:`.job` (what to
do), :mod:`.inputs` (the object files, their identities and fingerprints),
:mod:`.time_limit` (one object's time limit), :mod:`.one_object` (one object
on a worker, to its record), :mod:`.records` (the results folder:
``job.json``, the records, ``results.parquet``), :mod:`.workers` and
:mod:`.pool` (the local pool's processes), :mod:`.progress` (progress
lines), :mod:`.run` (the driver, :func:`run_dataset`), and
:mod:`.gripper_job` (labelled parallel-jaw grasps, ``--gripper``). The
package loads nothing until a name is asked for.

Examples
--------
>>> import tempfile
>>> from forceclosure.datasets import Job, run_dataset
>>> summary = run_dataset(["cube"], tempfile.mkdtemp(), Job(contact="soft", mu=0.5, top=1),
...                       workers=1, progress=False)
>>> summary.done
1
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy import lazy_names

_HOME = {
    **dict.fromkeys(["Job", "LabelJob"], "job"),
    **dict.fromkeys(["expand_inputs", "fingerprint", "record_name"], "inputs"),
    **dict.fromkeys(["ObjectTimeout", "deadline"], "time_limit"),
    **dict.fromkeys(["process_object"], "one_object"),
    **dict.fromkeys(["COLUMNS", "row_of", "write_table"], "records"),
    **dict.fromkeys(["Summary", "run_dataset"], "run"),
    **dict.fromkeys(["GRASP_COLUMNS", "GripperJob", "read_labels"], "gripper_job"),
}

__all__ = ["COLUMNS", "GRASP_COLUMNS", "GripperJob", "Job", "LabelJob", "ObjectTimeout",
           "Summary", "deadline", "expand_inputs", "fingerprint", "process_object",
           "read_labels", "record_name", "row_of", "run_dataset", "write_table"]

__getattr__, __dir__ = lazy_names(__name__, _HOME)

if TYPE_CHECKING:
    from .gripper_job import GRASP_COLUMNS, GripperJob, read_labels
    from .inputs import expand_inputs, fingerprint, record_name
    from .job import Job, LabelJob
    from .one_object import process_object
    from .records import COLUMNS, row_of, write_table
    from .run import Summary, run_dataset
    from .time_limit import ObjectTimeout, deadline
