"""The documentation site's MkDocs hooks (``hooks:`` in mkdocs.yml).

* The repository's README.md is the site's home page (``index.md``): one text for GitHub and the
  site. Its links into ``docs/`` are rewritten to be relative to the site's root, and a page's
  link to the README (``../README.md#figures``, which GitHub follows) to the home page.
* A page's link to a file of the repository outside ``docs/`` (``../scenarios/x.yaml``, which
  GitHub follows) is shown as the file's path in the repository: the site holds only docs/. A
  link to a file that does not exist stays, and fails the strict build.
* An experiment summary links the replay of every failed trial (``replays/<trial>.html``); the
  committed experiments do not keep their replays (about 1 GB), so such a link whose file is
  absent is shown as plain text ("replay not kept") instead of a link to nothing. Every other
  link is checked by ``mkdocs build --strict`` (tests/docs/test_site.py).
"""

from __future__ import annotations

import re
from pathlib import Path

from mkdocs.structure.files import File

#: A Markdown link or image target that starts in the repository's docs/ folder.
_INTO_DOCS = re.compile(r"(\]\()docs/")
#: A Markdown link whose target is a README.md, with its anchor.
_TO_README = re.compile(r"(\]\()((?:\.\./)+)README\.md([#)])")
#: A Markdown link (not an image) to a relative target: text, target, anchor.
_LINK = re.compile(r"(?<!!)\[([^\]]*)\]\(((?:\.\./)+[^)#\s]+)(#[^)\s]*)?\)")
#: A Markdown link to a trial's replay.
_REPLAY = re.compile(r"\[([^\]]*)\]\((replays/[^)\s]+\.html)\)")


def readme_as_home(readme: str) -> str:
    """The README's text with its ``docs/...`` links made relative to the docs folder."""
    return _INTO_DOCS.sub(r"\1", readme)


def on_files(files, config):
    """Adds the README as ``index.md`` (the home page)."""
    readme = Path(config["config_file_path"]).parent / "README.md"
    files.append(File.generated(config, "index.md", content=readme_as_home(readme.read_text())))
    return files


def on_page_markdown(markdown, page, config, files):
    """Points links to the repository's README at the home page, and unlinks replays that are
    not kept beside an experiment's summary."""
    docs = Path(config["docs_dir"]).resolve()
    folder = docs / Path(page.file.src_uri).parent
    readme = Path(config["config_file_path"]).resolve().parent / "README.md"

    def home(match: re.Match) -> str:
        if (folder / match.group(2) / "README.md").resolve() != readme:
            return match.group(0)
        up = "../" * len(Path(page.file.src_uri).parent.parts)
        return f"{match.group(1)}{up}index.md{match.group(3)}"

    def unlink(match: re.Match) -> str:
        if (folder / match.group(2)).is_file():
            return match.group(0)
        return f"{match.group(1)} not kept"

    def repository_file(match: re.Match) -> str:
        target = (folder / match.group(2)).resolve()
        root = readme.parent
        if target.is_relative_to(docs) or not target.is_relative_to(root) or not target.exists():
            return match.group(0)
        path = target.relative_to(root).as_posix()
        text = match.group(1)
        return text if path in text else f"{text} (`{path}`)"

    markdown = _TO_README.sub(home, markdown)
    return _REPLAY.sub(unlink, _LINK.sub(repository_file, markdown))
