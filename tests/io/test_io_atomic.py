"""Atomic writes: complete file or none; a failed writer leaves no partial file."""

import pytest

from rotorsfd.io import atomic


def test_write_text_and_csv(tmp_path):
    p = atomic.write_text(tmp_path / "sub" / "a.txt", "hello\n")
    assert p.read_text() == "hello\n"
    c = atomic.write_csv(tmp_path / "t.csv", ("mode", "whirl", "speed_rad_s"),
                         [(1, "forward", 811.3)])
    assert c.read_text().splitlines() == ["mode,whirl,speed_rad_s", "1,forward,811.3"]
    assert sorted(f.name for f in tmp_path.iterdir()) == ["sub", "t.csv"]


def test_failing_writer_leaves_no_partial_file(tmp_path):
    target = tmp_path / "result.csv"
    with pytest.raises(RuntimeError), atomic.atomic_path(target) as tmp:
        tmp.write_text("half a row,")
        raise RuntimeError("writer died midway")
    assert not target.exists()
    assert list(tmp_path.iterdir()) == []          # the temporary file is gone too


def test_failing_writer_keeps_previous_file(tmp_path):
    target = atomic.write_text(tmp_path / "result.json", '{"old": true}')
    with pytest.raises(ValueError), atomic.atomic_path(target) as tmp:
        tmp.write_text('{"new": ')
        raise ValueError("bad data")
    assert target.read_text() == '{"old": true}'
    assert [f.name for f in tmp_path.iterdir()] == ["result.json"]


def test_save_figure_atomic(tmp_path):
    from matplotlib.figure import Figure

    fig = Figure()
    fig.add_subplot().plot([0, 1], [1, 0])
    p = atomic.save_figure(fig, tmp_path / "f.png")
    assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [f.name for f in tmp_path.iterdir()] == ["f.png"]
