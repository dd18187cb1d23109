"""The one error of a scan that cannot be used: it names the file and the field, as the caller
gives it (:func:`setting`: a flag of ``gbh grasps`` or an argument of ``gbh_drake.grasps``)."""

from __future__ import annotations


class GraspsInputError(ValueError):
    """An input ``gbh grasps`` cannot use: ``<file>: <field>: <problem>`` (one line; the CLI
    says it and exits 2)."""

    def __init__(self, file, field: str, problem: str):
        where = f"{file}: {field}" if field else f"{file}"
        super().__init__(f"{where}: {' '.join(str(problem).split())}")
        self.file, self.field, self.problem = str(file), field, problem

    def __reduce__(self):  # picklable with its parts
        return type(self), (self.file, self.field, self.problem)


def setting(name: str, cli: bool, *, given: bool = False) -> str:
    """The setting ``name`` (``table_z``) as its caller names it: the flag ``--table-z`` of
    ``gbh grasps`` (``cli``), else the argument ``table_z`` of ``gbh_drake.grasps``
    (``given``: as a value is given to it, ``table_z=``)."""
    if cli:
        return "--" + name.replace("_", "-")
    return f"{name}=" if given else name
