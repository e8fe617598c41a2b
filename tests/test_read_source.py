"""read_source reads a file through its raw descriptor (run._read_bytes): the whole
text of a file, of a pipe that gives it in pieces, cut at READ_LIMIT, and the same
errors as a file object's open gives."""
from __future__ import annotations

import os
import threading
import time

import pytest

from momentum_cli import run


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes")
@pytest.mark.parametrize("limit", [10**6, 20])
def test_a_pipe_that_gives_its_text_in_pieces_is_read_to_its_end(tmp_path, monkeypatch, limit):
    monkeypatch.setattr(run, "FIRST_READ", 8)
    monkeypatch.setattr(run, "READ_LIMIT", limit)
    fifo = tmp_path / "p.mom"
    os.mkfifo(fifo)
    pieces = [b"let a = 1\n", b"let b = 2\n", b"let c = 3\n"]

    def write():
        try:
            with open(fifo, "wb", buffering=0) as fh:
                for p in pieces:
                    fh.write(p)
                    time.sleep(0.02)  # the reader sees each piece alone
        except BrokenPipeError:  # the reader stopped at its limit
            pass

    t = threading.Thread(target=write)
    t.start()
    try:
        text = run.read_source(str(fifo)).text
    finally:
        t.join()
    assert text == b"".join(pieces).decode()[:limit]


def test_errors_are_a_file_objects(tmp_path):
    with pytest.raises(FileNotFoundError):
        run.read_source(str(tmp_path / "missing.mom"))
    with pytest.raises(IsADirectoryError):
        run.read_source(str(tmp_path))
    p = tmp_path / "a.mom"
    p.write_bytes(b"\xef\xbb\xbflet a = 1\n")
    assert run.read_source(str(p)).text == "let a = 1\n"
