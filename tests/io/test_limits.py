"""Inputs are regular files, read within bounded time and memory.

Each hostile input runs in a subprocess with a timeout, so that a regression fails the
test instead of hanging the suite; the decompression bomb's peak memory is measured
there with ``resource.getrusage``."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from fogts.cli import app
from fogts.errors import DataError
from fogts.io.limits import MAX_LINE_BYTES, max_input_bytes
from fogts.io.reader import read_json, read_run

runner = CliRunner()

_READ = """
import resource, sys, time
t0 = time.perf_counter()
from fogts.errors import DataError
from fogts.io.reader import read_run
try:
    read_run(sys.argv[1])
    print("READ")
except DataError as exc:
    print("ERROR", exc)
peak_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print("PEAK_KB", peak_kb, "SECONDS", time.perf_counter() - t0)
"""


def _read_in_subprocess(path: Path | str, timeout: float = 30.0,
                        env: dict[str, str] | None = None) -> tuple[str, int, float]:
    """(error message or 'READ', peak RSS in kB, seconds) of read_run(path) in a child."""
    out = subprocess.run([sys.executable, "-c", _READ, str(path)], capture_output=True,
                         text=True, timeout=timeout, env={**os.environ, **(env or {})},
                         check=True).stdout.splitlines()
    peak = out[-1].split()
    return out[0], int(peak[1]), float(peak[3])


@pytest.mark.parametrize(("path", "kind"), [("/dev/zero", "a character device"),
                                            ("/dev/urandom", "a character device")])
def test_devices_are_refused_at_once(path: str, kind: str) -> None:
    if not os.path.exists(path):
        pytest.skip(f"{path} does not exist on this system")
    # the message is os.stat's verdict, so nothing was read (a read of /dev/zero would end
    # on the line-length limit instead); the timeout catches a hang without timing the test
    message, _, _ = _read_in_subprocess(path, timeout=20.0)
    assert message == f"ERROR {path!r} is {kind}, not a regular file; fogts reads regular " \
                      "files only"


def test_fifo_socket_and_directory_are_refused(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    message, _, _ = _read_in_subprocess(fifo, timeout=20.0)  # opening a FIFO would block
    assert "is a FIFO (named pipe), not a regular file" in message
    sock_path = tmp_path / "s.csv"
    with socket.socket(socket.AF_UNIX) as sock:
        sock.bind(str(sock_path))
        with pytest.raises(DataError, match=r"'.*s\.csv' is a socket, not a regular file"):
            read_run(sock_path)
    with pytest.raises(DataError, match="is a directory, not a file"):
        read_run(tmp_path)
    with pytest.raises(DataError, match=r"model 'pipe.csv' is a FIFO|is a FIFO"):
        read_json(fifo, "model")


def test_cli_refuses_dev_zero_in_one_line() -> None:
    res = runner.invoke(app, ["info", "/dev/zero"])
    assert res.exit_code == 2
    assert res.stderr == ("error: '/dev/zero' is a character device, not a regular file; "
                          "fogts reads regular files only\n")


def _bomb(path: Path, gib: int = 2) -> Path:
    """A .gz of ``gib`` GiB of b'0' on one line (about 9 MB), built in 4 MiB chunks."""
    comp = zlib.compressobj(1, zlib.DEFLATED, 31)  # wbits 31: gzip container
    chunk = b"0" * (4 << 20)
    with open(path, "wb") as fh:
        for _ in range(gib * 256):
            fh.write(comp.compress(chunk))
        fh.write(comp.flush())
    return path


def test_decompression_bomb_stops_under_1_gb(tmp_path: Path) -> None:
    bomb = _bomb(tmp_path / "bomb.csv.gz")
    assert bomb.stat().st_size < 20 << 20
    message, peak_kb, _ = _read_in_subprocess(bomb, timeout=60.0)
    assert message.startswith("ERROR ") and "line 1 is longer than 1 MiB" in message
    assert peak_kb < 1 << 20  # < 1 GB peak


def test_expansion_beyond_the_limit_stops(tmp_path: Path) -> None:
    path = tmp_path / "many.csv.gz"
    rows = b"".join(b"%d,%d\n" % (i, i % 7) for i in range(200_000))
    path.write_bytes(zlib.compress(b"time,rate\n" + rows, wbits=31))
    message, _, _ = _read_in_subprocess(path, env={"FOGTS_MAX_INPUT_BYTES": "1M"})
    assert message.startswith(f"ERROR {str(path)!r}: the stream decompresses to more than "
                              "the input limit of 1 MiB; oversized input is refused (set "
                              "FOGTS_MAX_INPUT_BYTES")
    assert _read_in_subprocess(path)[0] == "READ"  # the default limit reads it


def test_oversized_plain_file_is_refused_from_its_size(tmp_path: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "big.csv"
    path.write_text("time,rate\n" + "".join(f"{i},{i % 5}\n" for i in range(1000)))
    monkeypatch.setenv("FOGTS_MAX_INPUT_BYTES", "2K")
    assert max_input_bytes() == 2048
    with pytest.raises(DataError, match=r"the file has .* more than the input limit of "
                                        r"2 KiB; oversized input is refused"):
        read_run(path)
    monkeypatch.setenv("FOGTS_MAX_INPUT_BYTES", "lots")
    with pytest.raises(DataError, match="FOGTS_MAX_INPUT_BYTES must be a number of bytes "
                                        "such as 4000000000 or 8G; got 'lots'"):
        read_run(path)


def test_long_line_names_the_line(tmp_path: Path) -> None:
    path = tmp_path / "long.csv"
    path.write_bytes(b"time,rate\n0,1\n0.1," + b"1" * (MAX_LINE_BYTES + 10) + b"\n0.2,3\n")
    with pytest.raises(DataError, match=r"line 3 is longer than 1 MiB"):
        read_run(path)
    # many ordinary lines across chunk boundaries are fine
    ok = tmp_path / "ok.csv"
    ok.write_text("time,rate\n" + "".join(f"{i / 10},{i % 3}\n" for i in range(2_000_000)))
    assert read_run(ok).n == 2_000_000


def test_truncated_and_oversized_arrays(tmp_path: Path,
                                        monkeypatch: pytest.MonkeyPatch) -> None:
    good = tmp_path / "x.npy"
    np.save(good, np.arange(1000, dtype=np.float64))
    cut = tmp_path / "cut.npy"
    cut.write_bytes(good.read_bytes()[:4000])
    with pytest.raises(DataError, match=r"is truncated: its header declares \(1000,\) float64 "
                                        r"\(8000 bytes\) but the file holds"):
        read_run(cut, fs_hz=1.0)
    npz = tmp_path / "x.npz"
    np.savez(npz, rate=np.arange(1000, dtype=np.float64), fs_hz=10.0)
    monkeypatch.setenv("FOGTS_MAX_INPUT_BYTES", "4K")
    with pytest.raises(DataError, match=r"its arrays expand to .* more than the input limit"):
        read_run(npz)
    with pytest.raises(DataError, match=r"needs 7.81 KiB, more than the input limit"):
        read_run(good, fs_hz=1.0)


def test_read_json_is_bounded(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "m.json"
    path.write_text(json.dumps({"a": list(range(2000))}))
    assert read_json(path)["a"][-1] == 1999
    monkeypatch.setenv("FOGTS_MAX_INPUT_BYTES", "1K")
    with pytest.raises(DataError, match="oversized input is refused"):
        read_json(path)
