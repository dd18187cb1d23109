"""The one error of a scan that cannot be used: it names the file and the field."""

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
