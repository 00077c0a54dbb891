"""Cases of files in and out: output paths that cannot be written, trajectory files that are
not trajectories, a code cache that is damaged or cannot be written.

The tests run as root here, where a folder's permissions do not stop a write:
the read-only case then points into /sys (which refuses even root) instead.
"""

from __future__ import annotations

import os
import re
import stat
from pathlib import Path

from hostile.case import HostileCase

MODEL = "harmonic_oscillator"
SHORT = ("--t-end", "0.5")
GOOD_CSV = "t,x,x_dot,energy\n0,1,0,0.5\n0.1,0.995,-0.0998,0.5\n"


def _text(name: str, text: str):
    def setup(folder: Path) -> None:
        (folder / name).write_text(text)

    return setup


def _bytes(name: str, data: bytes):
    def setup(folder: Path) -> None:
        (folder / name).write_bytes(data)

    return setup


def _folder(name: str):
    def setup(folder: Path) -> None:
        (folder / name).mkdir()

    return setup


def _read_only_folder(folder: Path) -> None:
    """{dir}/ro: a folder nobody may write to, root included."""
    target = folder / "ro"
    if os.geteuid() != 0:
        target.mkdir(mode=0o555)
    elif Path("/sys").is_dir():
        target.symlink_to("/sys")  # sysfs: EACCES (or EROFS) for root too
    else:  # pragma: no cover - no sysfs: a path through a file fails for everybody
        target.write_text("not a folder")


def _huge(folder: Path) -> None:
    """A sparse file just over the reading limit: its size costs no disk."""
    from lagrangian.trajectory_files import MAX_TRAJECTORY_BYTES

    with open(folder / "huge.nc", "wb") as stream:
        stream.write(b"CDF\x01")
        stream.truncate(MAX_TRAJECTORY_BYTES + 1)


def _foreign_netcdf(folder: Path) -> None:
    """A valid netCDF-3 file of another program: a temperature series, none of our names."""
    import numpy as np
    from scipy.io import netcdf_file

    with netcdf_file(folder / "weather.nc", "w") as data:
        data.createDimension("time", 3)
        variable = data.createVariable("temperature", "d", ("time",))
        variable[:] = np.array([280.0, 281.5, 279.0])


def _edited_cache_entry(folder: Path) -> None:
    """The cached module of the model, edited: valid Python that exits 3 if it ever runs."""
    from lagrangian import load
    from lagrangian.codegen.cache import _HEADER
    from lagrangian.codegen.forms import symbolic_forms
    from lagrangian.codegen.numba import generated_source

    digest, _ = generated_source(symbolic_forms(load(MODEL).equations_of_motion(), {}))
    cache = folder / "cache" / "numba"
    cache.mkdir(parents=True)
    (cache / f"{digest}.py").write_text(_HEADER + "0" * 64 + "\nraise SystemExit(3)\n")


def _fifo(name: str):
    def setup(folder: Path) -> None:
        os.mkfifo(folder / name)

    return setup


def _device(name: str):
    """{dir}/name: a character device (a copy of the null device as root, else a link to it)."""

    def setup(folder: Path) -> None:
        if os.geteuid() == 0:
            os.mknod(folder / name, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
        else:  # pragma: no cover - a user cannot replace /dev/null anyway
            (folder / name).symlink_to("/dev/null")

    return setup


def _special_cases() -> list[HostileCase]:
    """Every command that writes a file refuses a FIFO or a device as its target."""
    commands = {
        "simulate": ("simulate", MODEL, *SHORT, "--out"),
        "export": ("export", MODEL, "--to", "c", "--out"),
        "plot": ("plot", MODEL, "--kind", "phase", *SHORT, "--out"),
        "animate": ("animate", MODEL, *SHORT, "--out"),
        "ensemble": ("ensemble", MODEL, "--grid", "x=0:1:2", *SHORT, "--out"),
    }
    suffixes = {"simulate": ".csv", "export": ".c", "plot": ".png", "animate": ".gif"}
    cases = []
    for command, argv in commands.items():
        name = "out" + suffixes.get(command, ".nc")
        for kind, setup, shown in (
            ("fifo", _fifo(name), "a FIFO"),
            ("device", _device(name), "a character device"),
        ):
            cases.append(
                HostileCase(
                    f"files-{command}-out-onto-{kind}",
                    (*argv, f"{{dir}}/{name}"),
                    error=rf"{re.escape(name)}: cannot write: it is {shown}.*not a regular file",
                    setup=setup,
                )
            )
    return cases


def _file(name: str):
    return _text(name, "a file, not a folder\n")


def _out(path: str, error: str, name: str, setup=None) -> HostileCase:
    return HostileCase(name, ("simulate", MODEL, *SHORT, "--out", path), error=error, setup=setup)


def _plot(file: str, error: str, name: str, setup) -> HostileCase:
    return HostileCase(
        name, ("plot", f"{{dir}}/{file}", "--out", "{dir}/p.png"), error=error, setup=setup
    )


CASES = [
    # -- output paths (checked before the run; the write maps the rest) --------------------
    _out(
        "{dir}/missing/run.csv",
        r"missing/run\.csv: cannot write: the folder .* does not exist",
        "files-out-missing-folder",
    ),
    _out(
        "{dir}/plain/run.csv",
        r"plain/run\.csv: cannot write: .*plain is not a folder",
        "files-out-under-a-file",
        _file("plain"),
    ),
    _out(
        "{dir}/ro/run.nc",
        r"ro/run\.nc: cannot write: .*(not writable|read-only)",
        "files-out-read-only-folder",
        _read_only_folder,
    ),
    _out(
        "{dir}/" + "x" * 300 + ".csv",
        r"x+\.csv: cannot write: the file name is too long",
        "files-out-name-too-long",
    ),
    *_special_cases(),
    HostileCase(
        "files-export-out-dev-null",
        ("export", MODEL, "--to", "c", "--out", "/dev/null"),
        error=r"/dev/null: cannot write: it is a character device, not a regular file",
    ),
    HostileCase(
        "files-export-out-link-to-dev-null",
        ("export", MODEL, "--to", "numpy", "--out", "{dir}/link.py"),
        error=r"/dev/null: cannot write: it is a character device",
        setup=lambda folder: (folder / "link.py").symlink_to("/dev/null"),
    ),
    _out(
        "{dir}/run.csv",
        r"run\.csv.* is a (directory|folder)",
        "files-out-is-a-folder",
        _folder("run.csv"),
    ),
    HostileCase(
        "files-plot-out-under-a-file",
        ("plot", "{dir}/run.csv", "--out", "{dir}/plain/p.png"),
        error=r"p\.png: cannot write: .*plain is not a folder",
        setup=lambda folder: (_file("plain")(folder), _text("run.csv", GOOD_CSV)(folder)),
    ),
    HostileCase(
        "files-ensemble-out-missing-folder",
        ("ensemble", MODEL, "--grid", "x=0:1:2", "--out", "{dir}/missing/runs.nc"),
        error=r"missing/runs\.nc: cannot write: the folder .* does not exist",
    ),
    HostileCase(
        "files-animate-out-under-a-file",
        ("animate", MODEL, "--out", "{dir}/plain/motion.gif"),
        error=r"motion\.gif: cannot write: .*plain is not a folder",
        setup=_file("plain"),
    ),
    HostileCase(
        "files-demo-out-dir-is-a-file",
        ("demo", "--out-dir", "{dir}/plain"),
        error=r"plain.* is a file",
        setup=_file("plain"),
    ),
    HostileCase(
        "files-demo-out-dir-under-a-file",
        ("demo", "--out-dir", "{dir}/plain/demo"),
        error=r"plain/demo: cannot write: .*plain is not a folder",
        setup=_file("plain"),
    ),
    # -- trajectory files given to plot -----------------------------------------------------
    _plot(
        "empty.nc",
        r"empty\.nc: is empty, not a trajectory file",
        "files-plot-empty-nc",
        _bytes("empty.nc", b""),
    ),
    _plot(
        "noise.nc",
        r"noise\.nc: is not a netCDF file",
        "files-plot-random-bytes-nc",
        _bytes("noise.nc", bytes(range(256)) * 4),
    ),
    _plot(
        "damaged.nc",
        r"damaged\.nc: is a damaged netCDF file",
        "files-plot-truncated-nc",
        _bytes("damaged.nc", b"CDF\x01\x00\x00\x00\x03\x00\x00\x00\x0a"),
    ),
    _plot(
        "hdf.nc",
        r"hdf\.nc: is netCDF-4",
        "files-plot-netcdf4",
        _bytes("hdf.nc", b"\x89HDF\r\n\x1a\n" + bytes(64)),
    ),
    _plot(
        "weather.nc",
        r"weather\.nc: holds no trajectory of lagrangian",
        "files-plot-foreign-netcdf",
        _foreign_netcdf,
    ),
    _plot("huge.nc", r"huge\.nc: is too large to be read", "files-plot-huge-file", _huge),
    _plot(
        "folder.nc",
        r"folder\.nc: is a folder, not a trajectory file",
        "files-plot-folder",
        _folder("folder.nc"),
    ),
    _plot("absent.csv", r"absent\.csv: no such file", "files-plot-missing-file", None),
    _plot("empty.csv", r"empty\.csv: is empty", "files-plot-empty-csv", _text("empty.csv", "")),
    _plot(
        "run.csv",
        r"run\.csv: has no column 'energy'",
        "files-plot-csv-missing-column",
        _text("run.csv", "t,x,x_dot\n0,1,0\n"),
    ),
    _plot(
        "run.csv",
        r"run\.csv: line 3 has 3 values, the header 4",
        "files-plot-csv-short-row",
        _text("run.csv", "t,x,x_dot,energy\n0,1,0,0.5\n0.1,1,0\n"),
    ),
    _plot(
        "run.csv",
        r"run\.csv: line 2, column 2: 'abc' is not a number",
        "files-plot-csv-non-numeric",
        _text("run.csv", "t,x,x_dot,energy\n0,abc,0,0.5\n"),
    ),
    _plot(
        "run.csv",
        r"run\.csv: has a time t that is not finite \(nan in row 2\)",
        "files-plot-csv-nan-time",
        _text("run.csv", GOOD_CSV.replace("0.1,", "nan,")),
    ),
    _plot(
        "run.csv",
        r"run\.csv: has a header but no rows",
        "files-plot-csv-header-only",
        _text("run.csv", "t,x,x_dot,energy\n"),
    ),
    _plot(
        "run.csv",
        r"run\.csv: is not a text file",
        "files-plot-csv-binary",
        _bytes("run.csv", b"t,x\n\xff\xfe\x00\x81"),
    ),
    # -- the code cache of the numba backend ----------------------------------------------
    HostileCase(
        "files-cache-path-is-a-file",
        ("simulate", MODEL, *SHORT, "--backend", "numba"),
        exit_code=0,
        output=r"final state",
        warning=r"lagrangian: warning: the code cache .*cache/numba cannot be used "
        r"\(not a directory\)",
        setup=_file("cache"),
        env=(("LAGRANGIAN_CACHE", "{dir}/cache"),),
    ),
    HostileCase(
        "files-cache-edited-entry-is-rebuilt",
        ("simulate", MODEL, *SHORT, "--backend", "numba"),
        exit_code=0,
        output=r"final state",
        setup=_edited_cache_entry,
        env=(("LAGRANGIAN_CACHE", "{dir}/cache"),),
    ),
]
