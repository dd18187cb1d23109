"""Lines of text in Meshcat's control panel (gbh_drake/viz/panel_text.py)."""

from gbh_drake.viz.meshcat_server import local_meshcat
from gbh_drake.viz.panel_text import MARK, WIDTH, PanelText


def test_lines_are_wrapped_unique_controls_without_quotes_and_are_replaced_whole():
    meshcat = local_meshcat()
    meshcat.AddButton("Scan")
    text = PanelText(meshcat)
    long = "the gripper's rods " * 5
    text.show(["same", "same", long, 'a "quoted" \\ path'])
    names = [n for n in meshcat.GetButtonNames() if n.startswith(MARK)]
    assert len(names) == len(set(names)) == len(text.lines)
    assert all(len(line) <= WIDTH for line in text.lines)
    assert text.lines[:2] == ["same", "same"] and text.lines[2].startswith("the gripper\u2019s")
    # A quote or a backslash in a button's name breaks Meshcat's page (its script): none left.
    assert not any(c in n for n in names for c in "'\"\\")
    text.show(["one line"])
    assert [n for n in meshcat.GetButtonNames() if n.startswith(MARK)] == [MARK + "one line"]
    text.clear()
    assert meshcat.GetButtonNames() == ["Scan"]
