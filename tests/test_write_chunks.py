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


def _flat(parts) -> str:
    return "\n".join(_flat(p) if isinstance(p, list) else p for p in parts)


def test_pieces_of_a_list_give_the_joined_bytes(monkeypatch):
    # render_parts' pieces (small, empty, one longer than a write, a list inside) are
    # joined in runs: the bytes of the text joined whole, for writes of every size
    lists = [
        [],
        [""],
        ["", ""],
        ["a"],
        [f"piece {i} — ω" * (i % 5) for i in range(300)],
        ["head", "x" * 700, "", "tail"],
        [["inner", "list"], "after", [], "more", ["x" * 90, ""], ""],
    ]
    for parts in lists:
        whole = _bytes(_flat(parts), None, monkeypatch)
        for chunk in (1, 7, 64, 1000, 1 << 20):
            assert _bytes(parts, chunk, monkeypatch) == whole, (parts[:3], chunk)
