"""Fuzzing the command line: whatever the file, a result or one line per problem, exit 0 or 2.

Generated JSON grasp files, ``.npz`` grasp files (with lying headers and cut
bytes) and polygon files are given to ``forceclosure analyze`` and
``forceclosure inspect``, run in this process as the command runs (standard
output and error strict UTF-8, as on a terminal). Every run must end in exit
status 0 or 2, never 1 (an internal error) or a traceback; every line on
standard error must be one of the command's own one-line messages, at least
one when the status is 2; and ``--json`` output must be strict JSON (no
``NaN``). The examples are derandomized and bounded (about 40 s in all, alone on a core).
"""

import contextlib
import io
import json
import os
import tempfile
import warnings
import zipfile

import numpy as np
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from forceclosure.app.cli import main

#: Examples per test: 200 (fewer where a test says), the same ones every run; set
#: FORCECLOSURE_FUZZ_EXAMPLES for a longer, random search.
_EXAMPLES = os.environ.get("FORCECLOSURE_FUZZ_EXAMPLES")
SETTINGS = settings(max_examples=int(_EXAMPLES or 200), deadline=None,
                    derandomize=not _EXAMPLES,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

# JSON texts that json.dumps cannot make: huge integers, the non-standard constants
RAW = ["1" + "0" * 400, "-" + "9" * 5000, "1e400", "-1e400", "NaN", "Infinity", "-Infinity",
       "1e-400", "0.0000000000000000000000000000001"]

extreme = st.one_of(
    st.sampled_from([0.0, -0.0, 1e-300, 1e-12, 1e12, 1e100, 1e101, 1e200, 1e308, -1e308,
                     2.0 ** 63, 5e-324, -1.0]),
    st.integers(-(10 ** 30), 10 ** 30), st.sampled_from(RAW).map(lambda raw: ("raw", raw)))
names = st.text(st.characters(categories=["L", "N", "Cc", "Cs", "Zl", "Zs"]), max_size=12)
scalars = st.one_of(extreme, names, st.booleans(), st.none())
junk = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                     st.dictionaries(names, inner, max_size=3)),
                    max_leaves=8)
unit = st.one_of(st.floats(0.1, 1), st.floats(-1, -0.1))


@st.composite
def good_contacts(draw, dim):
    """A well-formed contact: a point, an outward normal, a model and friction."""
    contact = {"point": draw(st.lists(st.floats(-2, 2), min_size=dim, max_size=dim)),
               "normal": draw(st.lists(unit, min_size=dim, max_size=dim)),
               "model": draw(st.sampled_from(["hard", "soft", "frictionless"])),
               "mu": draw(st.floats(0, 1.5))}
    if draw(st.integers(0, 4)) == 0:  # an edge or face contact
        more = draw(st.lists(st.lists(st.floats(-2, 2), min_size=dim, max_size=dim),
                             min_size=1, max_size=3))
        contact["points"] = [contact.pop("point"), *more]
    if draw(st.integers(0, 4)) == 0:
        contact["torsion"] = draw(st.floats(0, 0.1))
    return contact


@st.composite
def good_files(draw):
    """A well-formed grasp file of one to four grasps, planar or spatial."""
    grasps = []
    for _ in range(draw(st.integers(1, 3))):
        dim = draw(st.sampled_from([2, 3]))
        grasp = {"name": draw(names),
                 "contacts": draw(st.lists(good_contacts(dim), min_size=1, max_size=3))}
        if draw(st.integers(0, 4)) == 0:
            grasp["reference"] = draw(st.lists(st.floats(-1, 1), min_size=dim, max_size=dim))
        if draw(st.integers(0, 4)) == 0:
            grasp["length_scale"] = draw(st.floats(0.1, 10))
        grasps.append(grasp)
    top = {"grasps": grasps} if len(grasps) > 1 or draw(st.booleans()) else grasps[0]
    if draw(st.integers(0, 3)) == 0:
        top["cone"] = draw(st.sampled_from(["exact", {"edges": 8},
                                            {"edges": 4, "fit": "circumscribed"}]))
    return top


def _places(value, path=()):
    """Every place in a JSON value: (container, key) pairs."""
    if isinstance(value, dict):
        for key, item in value.items():
            yield value, key
            yield from _places(item)
    elif isinstance(value, list):
        for i, item in enumerate(value):
            yield value, i
            yield from _places(item)


@st.composite
def damaged(draw, good, values):
    """``good``, then up to three places replaced by ``values``, deleted, or given a stray
    key; about a third of the results are left as they were."""
    value = draw(good)
    for _ in range(draw(st.sampled_from([0, 0, 1, 1, 2, 3]))):
        places = list(_places(value))
        if not places or draw(st.integers(0, 19)) == 0:
            value = draw(junk)
            continue
        container, key = draw(st.sampled_from(places))
        action = draw(st.sampled_from(["replace"] * 4 + ["delete", "stray"]))
        if action == "replace":
            container[key] = draw(values)
        elif action == "delete":
            del container[key]
        elif isinstance(container, dict):
            container[draw(names)] = draw(junk)
    return value


grasp_files = damaged(good_files(), st.one_of(extreme, extreme, junk)).map(
    lambda value: _json_text(value))


def _json_text(value):
    """JSON text of ``value``, with ("raw", text) pairs written as that text."""
    raws = []

    def encode(v):
        if isinstance(v, tuple) and len(v) == 2 and v[0] == "raw":
            raws.append(v[1])
            return f"@RAW{len(raws) - 1}@"
        if isinstance(v, list | tuple):
            return [encode(x) for x in v]
        if isinstance(v, dict):
            return {k: encode(x) for k, x in v.items()}
        return v
    text = json.dumps(encode(value))
    for i, raw in enumerate(raws):
        text = text.replace(f'"@RAW{i}@"', raw)
    return text


def _run(argv):
    """``main(argv)`` as a process runs it: output strict UTF-8; warnings would be lines."""
    out = io.TextIOWrapper(io.BytesIO(), encoding="utf-8", errors="strict")
    err = io.TextIOWrapper(io.BytesIO(), encoding="utf-8", errors="strict")
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), \
            warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            status = main(argv)
        except SystemExit as e:  # a command line argparse refuses: one line, status 2
            status = e.code
    texts = []
    for stream in (out, err):
        stream.flush()
        texts.append(stream.buffer.getvalue().decode("utf-8"))
    return status, texts[0], texts[1], [str(w.message) for w in caught]


def _check(argv, json_output=False, problems=("forceclosure: error: ",)):
    """Run and check; ``problems``: the line prefixes that report a problem (``dataset``
    reports each object that failed or ran out of time, and goes on)."""
    status, out, err, caught = _run(argv)
    lines = err.splitlines()
    event(f"exit {status}" + (", something analysed" if any(
        v in out for v in ("closure", "none", "marginal", "vertices")) else ""))
    assert status in (0, 2), (status, err)
    assert all(line.startswith((*problems, "forceclosure: warning: ")) for line in lines), err
    assert status == 0 or any(line.startswith(problems) for line in lines), err
    assert all(len(line) < 2000 for line in lines)
    assert not caught, caught  # a warning on standard error is a line nobody asked for
    if json_output and out:
        def refuse(constant):
            raise AssertionError(f"{constant} in --json output")
        json.loads(out, parse_constant=refuse)
    return status


@settings(SETTINGS, max_examples=25)  # the quality (epsilon, least friction) takes time
@given(text=grasp_files, flags=st.sampled_from([[], ["--json"]] + [["--no-quality"],
                                               ["--json", "--no-quality"]] * 2))
def test_analyze_json_grasp_files(text, flags):
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "g.json")
        with open(path, "w", encoding="utf-8", errors="surrogatepass") as f:
            f.write(text)
        _check(["analyze", path, *flags], json_output="--json" in flags)


bad_floats = st.sampled_from([0.0, -1.0, 1e-300, 1e100, 1e101, 1e300, -1e308, np.nan, np.inf,
                              -np.inf])
dtypes = st.sampled_from(["<f4", "<f2", "|i1", "<i8", "|u1", "|b1", "<c16", "<U3", ">f8", "|O"])


@st.composite
def npz_files(draw):
    """A well-formed ``.npz`` grasp file, then damaged: bad values, dtypes, shapes, members,
    or bytes (cut, flipped, or a header claiming more rows than there are)."""
    n, k, d = draw(st.integers(0, 12)), draw(st.integers(1, 4)), draw(st.sampled_from([2, 3]))
    rng = np.random.default_rng(draw(st.integers(0, 2 ** 32 - 1)))
    members = {"points": rng.uniform(-1, 1, (n, k, d)), "normals": rng.normal(size=(n, k, d)),
               "mu": rng.uniform(0, 1, draw(st.sampled_from([(), (k,), (n, k)])))}
    if draw(st.booleans()):
        members["model"] = np.array(draw(st.one_of(
            st.sampled_from(["hard", "soft", "frictionless"]),
            st.lists(st.sampled_from(["hard", "soft", "frictionless"]), min_size=k,
                     max_size=k))))
    if draw(st.integers(0, 3)) == 0:
        members["torsion"] = rng.uniform(0, 0.1, draw(st.sampled_from([(), (k,), (n, k)])))
    if draw(st.integers(0, 3)) == 0:
        members["cone"] = np.array(draw(st.sampled_from(["exact", "8-inscribed",
                                                         "16-circumscribed"])))
    for _ in range(draw(st.sampled_from([0, 0, 1, 1, 2]))):
        name = draw(st.sampled_from(sorted(members)))
        damage = draw(st.sampled_from(["value", "value", "dtype", "shape", "delete", "extra",
                                       "text"]))
        array = members[name]
        if damage == "value" and array.size and array.dtype.kind == "f":
            array = array.copy()
            array.flat[draw(st.integers(0, array.size - 1))] = draw(bad_floats)
        elif damage == "dtype" and array.dtype.kind == "f":
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                array = array.astype(draw(dtypes))
        elif damage == "dtype":  # a string member as numbers
            array = np.arange(array.size, dtype=float)
        elif damage == "shape":
            array = array.reshape(-1) if array.ndim != 1 else array[:, None]
        elif damage == "text":
            array = np.array(draw(names))
        elif damage == "extra":
            members[draw(st.sampled_from(["extra", "points2", "mu"]))] = np.zeros(2)
        if damage == "delete":
            del members[name]
        elif damage != "extra":
            members[name] = array
    buffer = io.BytesIO()
    (np.savez_compressed if draw(st.booleans()) else np.savez)(buffer, **members)
    data = buffer.getvalue()
    fault = draw(st.sampled_from(["none"] * 12 + ["cut", "flip", "claim"]))
    if fault == "cut":
        data = data[:draw(st.integers(0, len(data)))]
    elif fault == "flip":
        i = draw(st.integers(0, len(data) - 1))
        data = data[:i] + bytes([data[i] ^ 0xFF]) + data[i + 1:]
    elif fault == "claim":  # a header claiming more rows than the member holds
        header = io.BytesIO()
        np.lib.format.write_array_header_1_0(header, {
            "descr": "<f8", "fortran_order": False,
            "shape": (draw(st.sampled_from([5, 10 ** 6, 3 * 10 ** 8, 10 ** 18])), 2, 2)})
        buffer = io.BytesIO()
        with zipfile.ZipFile(buffer, "w") as archive:
            for name in ("points", "normals"):
                archive.writestr(name + ".npy", header.getvalue() + bytes(draw(
                    st.sampled_from([0, 32, 100]))))
        data = buffer.getvalue()
    return data


@SETTINGS
@given(data=npz_files(), flags=st.sampled_from([[], ["--json"], ["--epsilon"]]),
       chunk=st.sampled_from(["1", "3", "65536"]), out=st.booleans())
def test_analyze_npz_grasp_files(data, flags, chunk, out):
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "g.npz")
        with open(path, "wb") as f:
            f.write(data)
        extra = ["--out", os.path.join(folder, "r.npz")] if out else []
        status = _check(["analyze", path, "--chunk", chunk, *flags, *extra],
                        json_output="--json" in flags)
        if out and status == 0:
            with np.load(os.path.join(folder, "r.npz")) as saved:
                assert int(saved["done"]) == len(saved["verdict"])
        assert not [name for name in os.listdir(folder) if name.endswith(".tmp")]


@st.composite
def good_polygons(draw):
    """A regular polygon (convex or a star), as a point list, ``outer`` or GeoJSON."""
    n = draw(st.integers(3, 9))
    radius = np.where(np.arange(n) % 2 & draw(st.booleans()), 0.5, 1.0)
    angle = 2 * np.pi * np.arange(n) / n
    ring = np.c_[radius * np.cos(angle), radius * np.sin(angle)].round(6).tolist()
    form = draw(st.sampled_from(["list", "outer", "geojson"]))
    if form == "list":
        return ring
    if form == "outer":
        return {"outer": ring, "name": draw(names)}
    return {"type": "Polygon", "coordinates": [[*ring, ring[0]]]}


polygons = damaged(good_polygons(), st.one_of(extreme, extreme, junk))


@SETTINGS
@given(shape=polygons, flags=st.sampled_from([[], ["--json"]]))
def test_inspect_polygon_files(shape, flags):
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "shape.json")
        with open(path, "w", encoding="utf-8") as f:
            f.write(_json_text(shape))
        _check(["inspect", path, *flags], json_output="--json" in flags)


# values for options, good and bad: numbers at and beyond their ranges, non-numbers
option_values = st.sampled_from(["0", "-1", "1", "2", "3", "4", "7", "12", "0.3", "0.8", "1e-9",
                                 "nan", "inf", "-inf", "1e400", "1e16", "abc", "", "0x10",
                                 " 2", "\u0661", "1_0"])
SYNTHESIS_OPTIONS = {
    "--fingers": option_values, "--mu": option_values, "--top": option_values,
    "--margin": option_values, "--seed": option_values,
    "--samples": st.sampled_from(["0", "-5", "60", "300", "abc", "1e3"]),
    "--contact": st.sampled_from(["hard", "soft", "frictionless", "HARD", ""]),
    "--construction": st.sampled_from(["maximal", "nguyen", "vertices", "mesh", "x"]),
    "--method": st.sampled_from(["auto", "faces", "mesh", "x"]),
    "--part": names,
}


@st.composite
def synthesis_flags(draw):
    chosen = draw(st.lists(st.sampled_from(sorted(SYNTHESIS_OPTIONS)), max_size=5,
                           unique=True))
    flags = ["--samples", "300"]  # bounded work whatever else is drawn
    for option in chosen:
        flags += [option, draw(SYNTHESIS_OPTIONS[option])]
    return flags + draw(st.sampled_from([[], ["--json"], ["--vertices"], ["--allow-open"]]))


@settings(SETTINGS, max_examples=60)  # each synthesizes: 6 s
@given(shape=st.one_of(polygons, st.sampled_from(["square", "triangle", "cube", "nothing"])),
       flags=synthesis_flags())
def test_synthesize_objects_and_options(shape, flags):
    """synthesize on damaged polygon files and bundled objects with options good and bad."""
    with tempfile.TemporaryDirectory() as folder:
        if isinstance(shape, str):
            target = shape
        else:
            target = os.path.join(folder, "shape.json")
            with open(target, "w", encoding="utf-8") as f:
                f.write(_json_text(shape))
        _check(["synthesize", target, *flags], json_output="--json" in flags)


@settings(SETTINGS, max_examples=25)
@given(shape=polygons, flags=synthesis_flags(),
       extra=st.sampled_from([[], ["--timeout", "nan"], ["--timeout", "0"], ["--retry-failed"],
                              ["--analyze"], ["--grasps", "{dir.x}"], ["--workers", "0"]]))
def test_dataset_on_damaged_objects(shape, flags, extra):
    """dataset in this process (one worker) over a damaged polygon and a good one: exit 0 or
    2, one line per problem, whatever the object and the options."""
    flags = [f for f in flags if f not in ("--vertices", "--part", "--allow-open")]
    with tempfile.TemporaryDirectory() as folder:
        target = os.path.join(folder, "shape.json")
        with open(target, "w", encoding="utf-8") as f:
            f.write(_json_text(shape))
        _check(["dataset", target, "square", "--out", os.path.join(folder, "out"),
                "--workers", "1", *flags, *extra], json_output="--json" in flags,
               problems=("forceclosure: error: ", "forceclosure: failed: ",
                         "forceclosure: timeout: "))


# -- grasps and export: meshes, options good and bad, label files damaged ---------------------

TETRA = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
GRASPS_OPTIONS = {
    "--count": st.sampled_from(["1", "3", "0", "-2", "1e12", "1e22", "x", ""]),
    "--width": st.sampled_from(["3", "0.5", "0", "-1", "1e300", "1e-300", "nan", "inf"]),
    "--mu": option_values, "--seed": option_values,
    "--gripper": st.sampled_from(["panda", "graspnet", "parallel-jaw", "robotiq", "x.urdf", ""]),
    "--pad-radius": st.sampled_from(["0", "0.01", "-1", "1e300", "nan"]),
    "--approaches": st.sampled_from(["1", "4", "0", "1e8", "-1"]),
    "--depths": st.sampled_from(["1", "2", "0", "1e9"]),
    "--tilt": st.sampled_from(["0", "0.5", "1", "2", "-0.5", "nan"]),
    "--clearance": st.sampled_from(["0", "0.001", "-1", "1e300"]),
    "--robust-samples": st.sampled_from(["2", "1", "1e8", "x"]),
    "--contact": st.sampled_from(["soft", "hard", "frictionless"]),
    "--graspnet-score": st.sampled_from(["friction", "epsilon", "x"]),
    "--task-mass": st.sampled_from(["1", "0", "-1", "1e100"]),
}


@st.composite
def grasps_flags(draw):
    chosen = draw(st.lists(st.sampled_from(sorted(GRASPS_OPTIONS)), max_size=5, unique=True))
    flags = ["--count", "3", "--width", "3"]  # bounded work whatever else is drawn
    for option in chosen:
        flags += [option, draw(GRASPS_OPTIONS[option])]
    return flags + draw(st.sampled_from(
        [[], ["--json"], ["--robust", "--robust-samples", "4"], ["--no-collision"],
         ["--support-plane"], ["--metrics"], ["--no-epsilon", "--no-least-friction"]]))


@settings(SETTINGS, max_examples=60)
@given(shape=st.sampled_from(["cube", "tetra", "damaged", "empty", "nothing", "square"]),
       flags=grasps_flags(), out=st.sampled_from(["", "labels.npz", "labels.npz/", "-"]))
def test_grasps_on_meshes_and_options(shape, flags, out):
    """grasps on bundled and written meshes (one damaged, one empty) with options good and
    bad: exit 0 or 2, one line per problem, never an internal error or a warning."""
    with tempfile.TemporaryDirectory() as folder:
        target = shape
        if shape in ("tetra", "damaged", "empty"):
            target = os.path.join(folder, f"{shape}.obj")
            text = {"tetra": TETRA, "damaged": TETRA.replace("f 2 3 4", "f 2 3 9"),
                    "empty": ""}[shape]
            with open(target, "w", encoding="utf-8") as f:
                f.write(text)
        extra = ["--out", os.path.join(folder, out) if out not in ("", "-") else out] \
            if out else []
        _check(["grasps", target, *flags, *extra], json_output="--json" in flags)


def _labels_file(folder: str) -> str:
    path = os.path.join(folder, "labels.npz")
    status, _, err, _ = _run(["grasps", "cube", "--width", "3", "--count", "4", "--out", path])
    assert status == 0, err
    return path


@settings(SETTINGS, max_examples=40)
@given(damage=st.sampled_from(["none", "none", "none", "cut", "drop", "meta", "junk"]),
       output=st.sampled_from([["--graspnet", "g.npy"], ["--acronym", "a.h5"], []]),
       flags=st.lists(st.sampled_from([
           ["--graspnet", "g.npy"], ["--acronym", "a.h5"], ["--graspnet-score", "epsilon"],
           ["--graspnet-score", "x"], ["--mesh-root", "nowhere"], ["--object", "cube"],
           ["--object", "nothing.obj"], ["--json"], ["--graspnet", ""], ["--acronym", "-"]]),
           max_size=2), cut=st.integers(0, 4000))
def test_export_of_label_files(damage, output, flags, cut):
    """export of a grasps --out file, whole or damaged (cut short, an array dropped, its
    meta made junk, not an archive): exit 0 or 2, one line per problem."""
    with tempfile.TemporaryDirectory() as folder:
        path = _labels_file(folder)
        if damage == "cut":
            with open(path, "rb") as f:
                data = f.read()
            with open(path, "wb") as f:
                f.write(data[:cut])
        elif damage in ("drop", "meta"):
            with np.load(path, allow_pickle=False) as z:
                arrays = dict(z)
            if damage == "drop":
                arrays.pop(sorted(arrays)[cut % len(arrays)])
            else:
                arrays["meta"] = np.array("{not json")
            np.savez(path, **arrays)
        elif damage == "junk":
            with open(path, "wb") as f:
                f.write(os.urandom(cut))
        argv = ["export", path]
        for flag in [output, *flags] if output else flags:
            argv += [flag[0]] + [os.path.join(folder, v) if v.endswith((".npy", ".h5")) else v
                                 for v in flag[1:]]
        _check(argv, json_output="--json" in argv)
