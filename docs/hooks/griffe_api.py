"""Griffe extension for the API reference: the mapped subpackages, and reST in docstrings.

* ``adapters/`` is installed as ``cdt_plugin.adapters`` (``[tool.setuptools.package-dir]``),
  but griffe reads packages from the file system, where ``cdt_plugin/`` has no ``adapters``
  folder. When griffe has loaded a package, each folder mapped to one of its subpackages is
  visited (statically, as griffe does: nothing is imported) and attached under its installed
  name, so ``::: cdt_plugin.adapters.shapely`` and cross-references to it work.
* The docstrings are numpy style with reST inline markup, rendered here as Markdown: a
  Sphinx role (``:func:`triangulate```) becomes a cross-reference to the object it names
  (resolved from the docstring's scope, as Sphinx does; plain code when it is not
  documented; the plain name in a ``name : type`` line, which griffe shows as code),
  and a doctest block outside an ``Examples`` section becomes a code block
  (Markdown would read ``>>>`` as quotes). The source files are not changed.
"""
from __future__ import annotations

import re
from pathlib import Path

import griffe

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
ROLE = re.compile(r":(?:py:)?(?:func|class|meth|mod|attr|data|exc|obj|const):`(~?)([\w.]+)`")
HEADER_RULE = re.compile(r"^\s*-{3,}\s*$")
ITEM_SECTIONS = {"Parameters", "Other Parameters", "Returns", "Yields", "Receives", "Raises", "Warns",
                 "Attributes"}


def mapped_subpackages(package: str) -> dict[str, Path]:
    """``{installed name: folder}`` for the subpackages of ``package`` mapped in pyproject.toml."""
    with open(ROOT / "pyproject.toml", "rb") as f:
        mapping = tomllib.load(f)["tool"]["setuptools"].get("package-dir", {})
    return {name: ROOT / folder for name, folder in mapping.items() if name.startswith(package + ".")}


def visit_file(loader: griffe.GriffeLoader, name: str, path: Path, parent: griffe.Module) -> griffe.Module:
    """Visit one source file as the module ``name`` of ``parent`` and attach it there."""
    code = path.read_text(encoding="utf-8-sig")
    if loader.store_source:
        loader.lines_collection[path] = code.splitlines()
    module = griffe.visit(name, path, code, extensions=loader.extensions, parent=parent,
                          docstring_parser=loader.docstring_parser,
                          docstring_options=loader.docstring_options,
                          lines_collection=loader.lines_collection,
                          modules_collection=loader.modules_collection)
    parent.set_member(name, module)
    return module


def attach_mapped_subpackages(pkg: griffe.Module, loader: griffe.GriffeLoader) -> None:
    """Attach the package-dir-mapped subpackages (their modules and subpackages) to ``pkg``."""
    for installed, folder in sorted(mapped_subpackages(pkg.name).items()):
        *parents, name = installed.split(".")[1:]
        parent = pkg
        for part in parents:
            parent = parent.get_member(part)
        if name in parent.members:
            continue
        visit_folder(loader, name, folder, parent)


def visit_folder(loader: griffe.GriffeLoader, name: str, folder: Path, parent: griffe.Module) -> None:
    """Visit a package folder as the module ``name`` of ``parent``: its modules, and its
    subpackages (folders with an ``__init__.py``) in turn."""
    package = visit_file(loader, name, folder / "__init__.py", parent)
    for path in sorted(folder.glob("*.py")):
        if path.stem != "__init__":
            visit_file(loader, path.stem, path, package)
    for sub in sorted(p for p in folder.iterdir() if (p / "__init__.py").is_file()):
        visit_folder(loader, sub.name, sub, package)


def cross_reference(obj: griffe.Object, match: re.Match) -> str:
    """A Sphinx role as an optional autorefs cross-reference to the object it names."""
    short, target = match.groups()
    head, _, rest = target.partition(".")
    try:
        identifier = obj.resolve(head) + ("." + rest if rest else "")
    except griffe.NameResolutionError:
        identifier = target
    title = target.rsplit(".", 1)[-1] if short else target
    return f'<autoref identifier="{identifier}" optional><code>{title}</code></autoref>'


def rest_to_markdown(obj: griffe.Object, text: str) -> str:
    """The reST markup of one docstring (of ``obj``) as Markdown.

    A role becomes a cross-reference, except on a section item's first line (``name :
    type``), which griffe shows as code: there it becomes the plain name. A doctest block
    (up to the next blank line) outside ``Examples`` (which griffe renders) is fenced.
    """
    lines, out, section, i = text.splitlines(), [], "", 0
    while i < len(lines):
        line = lines[i]
        if i + 1 < len(lines) and line.strip() and HEADER_RULE.match(lines[i + 1]):
            section = line.strip()
        if line.lstrip().startswith(">>>") and section != "Examples":
            indent = line[: len(line) - len(line.lstrip())]
            out.append(indent + "```pycon")
            while i < len(lines) and lines[i].strip():
                out.append(lines[i])
                i += 1
            out.append(indent + "```")
            continue
        if section in ITEM_SECTIONS and not line[:1].isspace():
            out.append(ROLE.sub(lambda m: m[2], line))
        else:
            out.append(ROLE.sub(lambda m: cross_reference(obj, m), line))
        i += 1
    return "\n".join(out)


def render_docstrings(obj: griffe.Object) -> None:
    """Rewrite ``obj``'s docstring and its members', recursively (see the module docstring)."""
    if obj.docstring is not None:
        obj.docstring.value = rest_to_markdown(obj, obj.docstring.value)
    for member in obj.members.values():
        if not member.is_alias:
            render_docstrings(member)


class ApiReference(griffe.Extension):
    """Mapped subpackages attached, docstrings' reST rendered as Markdown."""

    def on_package(self, *, pkg: griffe.Module, loader: griffe.GriffeLoader, **kwargs) -> None:
        state = pkg.extra["cdt_plugin_docs"]
        if not state.get("done"):            # once, whichever of the two events fires
            state["done"] = True
            attach_mapped_subpackages(pkg, loader)
            render_docstrings(pkg)

    on_package_loaded = on_package           # its older name (griffe 1.7 fires this one)
