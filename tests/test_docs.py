"""The documentation stays honest: README.md is the front door (at most 300 lines), docs/ holds
the reference with a table of contents, every relative link and image resolves (anchors too),
and every ``tactile_core...`` path the pages name exists and imports without a warning.

The import paths of 0.1 and 0.2 that went in 0.3 are named only in CHANGELOG.md, which is not
read here: a page that names one fails, as that path no longer imports.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = [ROOT / "README.md", *sorted(DOCS.glob("*.md"))]
README_MAX_LINES = 300

#: Paths the docs may name that a build creates (not in the repository).
GENERATED = ("firmware/build/",)
REPO_PATH = re.compile(r"^(?:tactile_core|app|tests|firmware|assets|docs|\.ci)/[\w./-]*$")

FENCE = re.compile(r"^```.*?^```[ \t]*$", re.S | re.M)
INLINE_CODE = re.compile(r"(`+)(.+?)\1", re.S)
LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HTML_SRC = re.compile(r"""<(?:img|a)\b[^>]*?\b(?:src|href)=["']([^"']+)["']""", re.I)
DOTTED = re.compile(r"\btactile_core(?:\.[A-Za-z_]\w*)+")
FROM_IMPORT = re.compile(
    r"^[ \t]*from[ \t]+(tactile_core[\w.]*)[ \t]+import[ \t]+(?:\(([\w\s,]+)\)|([\w \t,]+))", re.M
)


def rel(path: Path) -> str:
    return str(path.relative_to(ROOT))


def prose(text: str) -> str:
    """The text without fenced blocks and inline code (links there are not links)."""
    return INLINE_CODE.sub("", FENCE.sub("", text))


def code(text: str) -> list[str]:
    """Fenced blocks and inline code spans."""
    blocks = FENCE.findall(text)
    spans = [m.group(2) for m in INLINE_CODE.finditer(FENCE.sub("", text))]
    return blocks + spans


def slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link keeps its text
    text = re.sub(r"[^\w\- ]", "", text.strip().lower())
    return text.replace(" ", "-")


def anchors(path: Path) -> set[str]:
    found, seen = set(), {}
    for line in FENCE.sub("", path.read_text()).splitlines():
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if m:
            base = slug(m.group(1))
            n = seen.get(base, 0)
            found.add(base if n == 0 else f"{base}-{n}")
            seen[base] = n + 1
    return found


def links(path: Path) -> list[str]:
    text = prose(path.read_text())
    return LINK.findall(text) + HTML_SRC.findall(text)


def test_the_pages_were_found():
    # a glob that found nothing would pass every check below
    assert (DOCS / "README.md").exists() and (DOCS / "architecture.md").exists()
    assert len(PAGES) > 5
    assert sum(len(links(p)) for p in PAGES) > 20


def test_slugs_follow_github():
    assert slug("Part 1, threshold → μ") == "part-1-threshold--μ"
    assert slug("Experiment 2: trials needed for the estimate to settle") == (
        "experiment-2-trials-needed-for-the-estimate-to-settle"
    )
    assert slug("The paper's four methods") == "the-papers-four-methods"


def test_readme_is_a_front_door():
    lines = len((ROOT / "README.md").read_text().splitlines())
    assert lines <= README_MAX_LINES, f"README.md has {lines} lines (at most {README_MAX_LINES})"


def test_the_test_command_sits_right_after_its_marker():
    # .ci/run runs the fenced block that directly follows the marker
    lines = (ROOT / "README.md").read_text().splitlines()
    at = lines.index("<!-- test-command -->")
    assert lines[at + 1].startswith("```")
    command = lines[at + 2]
    assert lines[at + 3] == "```"
    assert command.startswith("python3 -m venv .venv") and "pytest" in command


def test_the_setup_command_runs_as_root_without_sudo_and_without_a_terminal():
    """Before: `sudo apt-get install ...`: "sudo: command not found" (status 127) as root in a
    container, and without -y apt-get asks and reads "Abort." from a closed standard input."""
    text = (ROOT / "README.md").read_text()
    setup = text.split("## Set up", 1)[1].split("```bash\n", 1)[1].split("\n", 1)[0]
    steps = [step.strip() for step in setup.split("&&")]
    apt = [step for step in steps if " apt-get " in f" {step} "]
    assert apt and all(step.startswith("$(command -v sudo) apt-get ") for step in apt)
    assert any(step.startswith("$(command -v sudo) apt-get install -y ") for step in apt)
    assert steps[-1] == ".venv/bin/tactile-tuner"  # it ends by starting the tuner: the README
    assert "closing\nthe window (or Ctrl-C in the terminal) gives the prompt back" in text  # says


@pytest.mark.parametrize("page", PAGES, ids=rel)
def test_every_relative_link_and_image_resolves(page):
    broken = []
    for target in links(page):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # https:, mailto:, ...
            continue
        path_part, _, anchor = target.partition("#")
        dest = (page.parent / path_part).resolve() if path_part else page
        if not dest.exists():
            broken.append(f"{target}: no file {dest}")
        elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
            broken.append(f"{target}: no heading #{anchor} in {rel(dest)}")
    assert broken == [], f"{rel(page)}:\n" + "\n".join(broken)


def test_the_table_of_contents_links_every_page():
    toc = DOCS / "README.md"
    linked = {(DOCS / t.partition("#")[0]).resolve() for t in links(toc)}
    missing = [rel(p) for p in DOCS.glob("*.md") if p != toc and p.resolve() not in linked]
    assert missing == [], f"docs/README.md does not link {missing}"


@pytest.mark.parametrize("page", PAGES, ids=rel)
def test_every_repository_path_named_in_code_exists(page):
    missing = []
    for snippet in code(page.read_text()):
        for token in re.split(r"[\s(),;:=]+", snippet):
            token = token.strip("'\"")
            in_repo = REPO_PATH.match(token) and not token.startswith(GENERATED)
            if in_repo and not (ROOT / token).exists():
                missing.append(token)
    assert missing == [], f"{rel(page)} names missing files: {missing}"


def named_paths() -> tuple[dict[str, list[str]], dict[str, set[str]]]:
    """``{dotted path: [pages]}`` and ``{module: names imported from it}``."""
    paths: dict[str, list[str]] = {}
    imports: dict[str, set[str]] = {}
    for page in PAGES:
        text = page.read_text()
        for snippet in code(text):
            for path in DOTTED.findall(snippet):
                paths.setdefault(path, []).append(rel(page))
            for module, grouped, names in FROM_IMPORT.findall(snippet):
                wanted = {n.strip() for n in (grouped or names).split(",") if n.strip()}
                imports.setdefault(module, set()).update(wanted)
    return paths, imports


#: Run in a fresh interpreter with warnings as errors: each path is a module, or a module and an
#: attribute chain.
PROBE = r"""
import importlib, json, sys, warnings
warnings.simplefilter("error")
paths, imports = json.loads(sys.stdin.read())
problems = {}

def resolve(path):
    parts = path.split(".")
    for i in range(len(parts), 0, -1):
        name = ".".join(parts[:i])
        try:
            obj = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name and (name == exc.name or name.startswith(exc.name + ".")):
                continue
            raise
        for attr in parts[i:]:
            obj = getattr(obj, attr)
        return obj
    raise ImportError(f"no module {parts[0]}")

for path in paths:
    try:
        resolve(path)
    except Exception as exc:
        problems[path] = f"{type(exc).__name__}: {exc}"
for module, names in imports.items():
    for name in names:
        try:
            resolve(f"{module}.{name}")
        except Exception as exc:
            problems[f"from {module} import {name}"] = f"{type(exc).__name__}: {exc}"
print(json.dumps(problems))
"""


def probe(paths, imports) -> dict[str, str]:
    payload = json.dumps([sorted(paths), {m: sorted(n) for m, n in imports.items()}])
    out = subprocess.run(
        [sys.executable, "-W", "error", "-c", PROBE],
        input=payload,
        capture_output=True,
        text=True,
        timeout=120,
        cwd=ROOT,
    )
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def test_every_module_path_in_the_docs_imports_without_a_warning():
    paths, imports = named_paths()
    assert len(paths) > 10, "the docs name fewer tactile_core paths than expected: parser broken?"
    problems = probe(paths, imports)
    report = []
    for path, why in sorted(problems.items()):
        module = path.split()[1] if path.startswith("from ") else path
        report.append(f"{path} (in {', '.join(sorted(set(paths.get(module, []))))}): {why}")
    assert problems == {}, "\n".join(report)
