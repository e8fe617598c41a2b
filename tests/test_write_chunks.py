"""solve's writer: a long report written in pieces gives the same bytes as written whole."""
import io

from momentum_cli import solve_cmd


def _bytes(text: str, chunk: int | None, monkeypatch) -> bytes:
    raw = io.BytesIO()
    out = io.TextIOWrapper(raw, encoding="ascii", errors="backslashreplace", newline="\r\n")
    if chunk is None:
        out.write(text)
    else:
        monkeypatch.setattr(solve_cmd, "WRITE_CHUNK", chunk)
        solve_cmd._write_text(out, text)
    out.flush()
    return raw.getvalue()


def test_pieces_give_the_same_bytes(monkeypatch):
    # non-ASCII (escaped), newlines (translated) and a text not a multiple of the piece
    text = "".join(f"line {i}: v = {i * 0.5} m/s — ω\n" for i in range(500)) + "end"
    whole = _bytes(text, None, monkeypatch)
    for chunk in (1, 7, 64, 1000, len(text), len(text) + 1):
        assert _bytes(text, chunk, monkeypatch) == whole
