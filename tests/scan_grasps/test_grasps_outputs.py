"""``gbh grasps``'s outputs: each path is checked before the work (one line naming it and its
option, exit 2), and --out and --html are written together, whole or not at all."""

from pathlib import Path

import pytest
import trimesh

from gbh_drake.cli import main
from gbh_drake.outputs import OutputError
from gbh_drake.scan_grasps.cli import write_together


@pytest.fixture
def box(tmp_path):
    path = tmp_path / "box.stl"
    trimesh.creation.box([0.08, 0.08, 0.1]).apply_translation([0.55, 0.0, 0.05]).export(path)
    return path


def _line(capsys) -> str:
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and "Traceback" not in err, (out, err)
    return err.strip()


def test_an_html_that_cannot_be_written_leaves_the_out_file_as_it_was(tmp_path, box, capsys):
    new, old = tmp_path / "part.json", tmp_path / "old.json"
    old.write_text("the previous grasps\n")
    for out in (new, old):
        assert main(["grasps", str(box), "--out", str(out), "--html",
                     str(tmp_path / "missing" / "x.html")]) == 2
        assert _line(capsys) == (f"gbh: cannot write outputs: {tmp_path / 'missing' / 'x.html'}: "
                                 f"--html: its folder {tmp_path / 'missing'} does not exist")
    assert not new.exists() and old.read_text() == "the previous grasps\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["box.stl", "old.json"]


@pytest.mark.parametrize(("out", "problem"), [
    ("missing/g.json", "its folder {tmp}/missing does not exist"),
    ("box.stl/g.json", "its folder {tmp}/box.stl is not a folder"),
    (".", "is a folder"),
])
def test_an_out_that_cannot_be_written_is_one_line(tmp_path, box, capsys, out, problem):
    path = tmp_path / out
    assert main(["grasps", str(box), "--out", str(path)]) == 2
    assert _line(capsys) == (f"gbh: cannot write outputs: {path}: --out: "
                             f"{problem.format(tmp=tmp_path)}")


def test_out_and_html_must_be_two_files(tmp_path, box, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["grasps", str(box), "--out", str(tmp_path / "g"), "--html",
              str(tmp_path / "." / "g")])
    assert exit_.value.code == 2
    assert capsys.readouterr().err.endswith(
        f"gbh: error: --html {tmp_path / '.' / 'g'}: the same file as --out\n")
    assert not (tmp_path / "g").exists()


def test_files_are_written_together_or_none(tmp_path):
    """The second file fails when written: the first is not written either, and no temporary
    file is left."""
    first = tmp_path / "a.json"
    first.write_text("old\n")
    with pytest.raises(OutputError) as error:
        write_together([(first, "new\n"), (tmp_path / "gone" / "b.html", "page")])
    assert str(error.value) == (f"{tmp_path / 'gone' / 'b.html'}: could not write it (No such "
                                "file or directory)")
    assert first.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["a.json"]
    write_together([(first, "new\n"), (tmp_path / "b.html", "page")])
    assert first.read_text() == "new\n" and (tmp_path / "b.html").read_text() == "page"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json", "b.html"]


def test_a_pipe_or_device_is_written_into_not_replaced(tmp_path):
    """``--out /dev/null`` (or a named pipe) gets the bytes; a rename would replace the device
    node with a file (as root it can: /dev/null became a regular file once)."""
    import os
    import stat
    import threading

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_text()))
    reader.start()
    write_together([(fifo, "the grasps\n")])
    reader.join(timeout=10)
    assert got == ["the grasps\n"] and stat.S_ISFIFO(fifo.stat().st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe"]  # nothing staged beside it
    write_together([(Path(os.devnull), "nothing\n")])
    assert stat.S_ISCHR(Path(os.devnull).stat().st_mode)
