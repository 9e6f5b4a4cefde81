"""MkDocs hook: the README's guides, included in the docs pages, keep working links.

The guides are written once, in README.md, and included by mkdocs-include-markdown-plugin
with their links left as they are in the README (``rewrite_relative_urls: false``). Two
kinds of link need help on the site:

* a repository file the README links to (``examples/dude_vs_earcut.png``) is added to the
  site at the same relative path, so the link resolves from every page;
* an anchor into another README section (``[GIS at scale](#gis-at-scale)``) may now be on
  another page: it becomes an autorefs cross-reference (``[GIS at scale][gis-at-scale]``),
  which mkdocs-autorefs resolves to the page holding that heading, or reports in the build.
"""
from __future__ import annotations

import re
from pathlib import Path

from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
LINK = re.compile(r"\]\(([^)#\s]+)\)")
ANCHOR_LINK = re.compile(r"\]\(#([\w-]+)\)")


def readme_files() -> list[str]:
    """The repository files (not pages, not URLs) that README.md links to."""
    links = LINK.findall(README.read_text(encoding="utf-8"))
    return sorted({link for link in links
                   if "://" not in link and not link.endswith(".md") and (ROOT / link).is_file()})


def on_files(files, config):
    """Serve every repository file the README links to at its repository path."""
    for link in readme_files():
        if files.get_file_from_path(link) is None:
            files.append(File(link, str(ROOT), config["site_dir"], config["use_directory_urls"]))
    return files


def on_page_markdown(markdown, page, config, files):
    """Turn in-README anchor links into cross-references that work across pages."""
    return ANCHOR_LINK.sub(r"][\1]", markdown)
