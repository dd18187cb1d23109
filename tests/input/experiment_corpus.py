"""The experiment file's bad-input corpus: experiment files a user might write, each with its
exact outcome through ``gbh experiment`` (exit code 2, one line, nothing written):

    gbh: invalid experiment: <file>[ (--set '...')]: <field> (line N): <problem>

as for a scenario (``input_corpus.py``): ``field=""`` is the file as a whole (``<file>: line N,
column C: <problem>``), ``line=None`` no line. ``@BASE@`` in a text is the packaged default
scenario; ``files`` are written beside the experiment file. ``test_experiment_corpus.py`` runs
them.
"""

from __future__ import annotations

from input_corpus import CUBE_OBJ, Case

#: The lines every case starts with (lines 1-2), unless its text starts with ``!raw``.
HEAD = "base: @BASE@\nobjects: [box]\n"


def _c(id, text, field, line, expect, **kw) -> Case:
    if isinstance(text, str) and text.startswith("!raw\n"):
        text = text[len("!raw\n"):]
    elif isinstance(text, str):
        text = HEAD + text
    return Case(id, text, field, line, expect, **kw)


CASES: list[Case] = [
    # ---- the file as a whole (as the scenario's) --------------------------------------------
    _c("latin1_comment", ("# caf\xe9\n" + HEAD).encode("latin-1"), "", 1,
       "is not UTF-8 text (byte 0xe9)"),
    _c("utf16", HEAD.encode("utf-16"), "", None, "is UTF-16 text; save it as UTF-8"),
    _c("nul_byte", (HEAD + "trials: 1\x00\n").encode(), "", 3, "NUL byte"),
    _c("syntax", "trials: [\n", "", 4, "not valid YAML"),
    _c("root_list", "!raw\n- base: x\n", "", 1, "an experiment is a mapping of fields"),
    _c("two_documents", "---\ntrials: 2\n", "", 3, "expected a single document"),
    # ---- empty documents are the defaults, which list no objects ------------------------------
    _c("comment_only", "!raw\n# nothing yet\n", "objects", None,
       "list at least one object of the set (gbh objects list), or give an object_set; the "
       "defaults (an empty file) have none"),
    _c("dashes_only", "!raw\n---\n", "objects", None, "the defaults (an empty file) have none"),
    _c("null_document", "!raw\n~\n", "objects", None, "the defaults (an empty file) have none"),
    _c("no_objects", "!raw\nbase: @BASE@\n", "objects", None, "list at least one object"),
    # ---- a key given twice (the last one would win) -------------------------------------------
    _c("dup_trials", "trials: 2\ntrials: 3\n", "trials", 4, "given twice (first at line 3); "
                                                            "remove one"),
    _c("dup_in_overrides", "methods:\n- name: a\n  overrides:\n    grasp_method: gbh\n"
                           "    grasp_method: antipodal\n",
       "methods[0].overrides.grasp_method", 7, "given twice (first at line 6)"),
    _c("dup_in_flow_overrides", "methods: [{name: a, overrides: {scan: {num_views: 1, "
                                "num_views: 2}}}]\n",
       "methods[0].overrides.scan.num_views", 3, "given twice"),
    _c("dup_in_text_overrides", "methods:\n- name: a\n  overrides: \"seed_: 1\\nscan: {}\\n"
                                "scan: {}\"\n",
       "methods[0].overrides.scan", 5, "given twice"),
    _c("dup_in_base_overrides", "base_overrides: {max_time: 9, max_time: 10}\n",
       "base_overrides.max_time", 3, "given twice"),
    _c("dup_method_key", "methods:\n- name: a\n  name: b\n", "methods[0].name", 5, "given twice"),
    # ---- fields the experiment sets for every trial -----------------------------------------
    _c("overrides_object_name", "methods:\n- name: a\n  overrides: {object: {name: kettle}}\n",
       "methods[0].overrides.object.name", 5, "each trial's object is one of the experiment's "
                                              "objects: the experiment sets it for every trial"),
    _c("overrides_seed", "methods:\n- name: a\n  overrides:\n    seed: 4\n",
       "methods[0].overrides.seed", 6, "each trial's seed comes from the experiment's seed"),
    _c("overrides_random_pose", "methods:\n- name: a\n  overrides: {object: {random_pose: "
                                "{x: [0.5, 0.6]}}}\n",
       "methods[0].overrides.object.random_pose", 5, "drawn from the experiment's pose"),
    _c("overrides_mesh", "methods:\n- name: a\n  overrides: {object: {mesh: cube.obj}}\n",
       "methods[0].overrides.object.mesh", 5, "named objects of the set"),
    _c("overrides_text_seed", "methods:\n- name: a\n  overrides: 'seed: 4'\n",
       "methods[0].overrides.seed", 5, "the experiment sets it for every trial"),
    _c("overrides_output_dir", "methods:\n- name: a\n  overrides: {output_dir: /tmp/x}\n",
       "methods[0].overrides.output_dir", 5, "writes into its own folder"),
    _c("base_overrides_object", "base_overrides:\n  object: {name: kettle}\n",
       "base_overrides.object.name", 4, "the experiment sets it for every trial"),
    _c("base_mesh", "!raw\nbase: mesh_base.yaml\nobjects: [box]\n", "base", 1,
       "mesh_base.yaml: object.mesh (line 2): an experiment runs the named objects of its "
       "objects list, not a mesh file",
       files={"mesh_base.yaml": "object:\n  mesh: cube.obj\n  name: ''\n", "cube.obj": CUBE_OBJ}),
    # ---- ranges (declared beside the fields) and the number of trials --------------------------
    _c("trials_billion", "trials: 1000000000\n", "trials", 3,
       "must be an integer in [1, 1000], got 1000000000"),
    _c("trials_zero", "trials: 0\n", "trials", 3, "must be an integer in [1, 1000], got 0"),
    _c("too_many_trials", "!raw\nbase: @BASE@\nobjects: [box, kettle, mug_classic]\n"
                          "trials: 1000\n", "trials", 3,
       "3 objects x 1000 trials x 4 methods x 1 protocols are 12000 trials; at most 10000"),
    _c("seed_negative", "seed: -1\n", "seed", 3, "must be an integer in [0, "),
    _c("trials_word", "trials: many\n", "trials", 3, "expected an integer, got 'many'"),
    _c("trials_typo", "trails: 5\n", "trails", 3, "unknown field (did you mean 'trials'?"),
    _c("objects_string", "!raw\nbase: @BASE@\nobjects: box\n", "objects", 2,
       "expected a list, got 'box'"),
    # ---- a method's overrides, located in the experiment file --------------------------------
    _c("overrides_range", "methods:\n- name: a\n  overrides:\n    scan: {num_views: 0}\n",
       "methods[0].overrides.scan.num_views", 6, "must be an integer in [1, 100], got 0"),
    _c("overrides_unknown", "methods:\n- name: a\n  overrides: {grasp_methd: gbh}\n",
       "methods[0].overrides.grasp_methd", 5, "unknown field (did you mean 'grasp_method'?"),
    _c("overrides_task", "methods:\n- name: a\n  overrides: {task: settle}\n",
       "methods[0].overrides.task", 5, "an experiment picks (task: pick)"),
    # ---- --set texts --------------------------------------------------------------------------
    _c("set_duplicate", "trials: 1\n", "trials", 2, "given twice (first at line 1)",
       overrides=("trials: 1\ntrials: 2",), origin=" (--set 'trials: 1\\ntrials: 2')"),
    _c("set_range", "trials: 1\n", "trials", 1, "must be an integer in [1, 1000]",
       overrides=("trials: 5000",), origin=" (--set 'trials: 5000')"),
]
