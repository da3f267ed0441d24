"""The documentation site's build rules (tools/mkdocs_hooks.py, mkdocs.yml) and the README's promises
about it: feature pages join the nav when they exist and never break the strict build when they do not,
the speed table is the one tools/speed_table.py prints, links out of docs/ become paths, and the
README's test command is the one CI runs."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import yaml

from tests.conftest import REPO

sys.path.insert(0, str(REPO / "tools"))
import mkdocs_hooks  # noqa: E402
import speed_table  # noqa: E402

sys.path.pop(0)


def nav_files(nav) -> set[str]:
    return mkdocs_hooks._named(nav)


def config_yaml() -> dict:
    class Loader(yaml.SafeLoader):
        pass

    Loader.add_multi_constructor("!", lambda loader, suffix, node: None)  # mkdocs' !!python tags
    return yaml.load((REPO / "mkdocs.yml").read_text(), Loader=Loader)


def test_every_page_the_nav_names_exists_and_strict_reports_unlisted_pages_only_as_info():
    cfg = config_yaml()
    missing = [p for p in nav_files(cfg["nav"]) if not (REPO / "docs" / p).is_file() and not p.startswith("examples/")]
    assert not missing
    assert cfg["strict"] is True and cfg["validation"]["nav"]["omitted_files"] == "info"
    assert set(mkdocs_hooks.OPTIONAL).isdisjoint(nav_files(cfg["nav"]))  # optional pages come from the hook


def test_optional_and_unknown_pages_join_the_nav_only_when_present(tmp_path):
    docs = tmp_path / "docs"
    (docs / "guide").mkdir(parents=True)
    for page in ("index.md", "cameras.md", "lenses.md", "stereo.md", "other.md", "guide/extra.md"):
        (docs / page).write_text("# page\n")
    nav = [{"Home": "index.md"}, {"User guide": []}, {"Reference": [{"Conventions": "conventions.md"}]},
           {"About this site": "site.md"}]
    out = mkdocs_hooks.on_config({"docs_dir": str(docs), "nav": nav})["nav"]
    assert {"Camera files and calibration": "cameras.md"} in out[1]["User guide"]
    assert {"Lens models": "lenses.md"} in out[2]["Reference"]
    assert "robustness.md" not in nav_files(out) and "design.md" not in nav_files(out)  # absent: left out
    assert {"Stereo 360": "stereo.md"} in out[1]["User guide"]
    assert {"More": ["guide/extra.md", "other.md"]} in out and out[-1] == {"About this site": "site.md"}


def test_speed_page_gets_the_table_of_bench_results():
    records = [json.loads(p.read_text()) for p in sorted((REPO / "bench-results").glob("*.json"))]
    page = mkdocs_hooks._fill_speed(f"intro\n{speed_table.START}\nold\n{speed_table.END}\nafter\n")
    assert page.startswith("intro\n") and page.endswith("after\n") and "old" not in page
    assert speed_table.table(records) in page and page.count("| ") > 50


def test_links_out_of_docs_become_repository_paths():
    text = "see [the engine](../lenslab/warp/engine.py), [v360](v360.md) and [web](https://x.org/a.md)"
    assert mkdocs_hooks._outside_links(text, "guide.md") == (
        "see the engine (`lenslab/warp/engine.py`), [v360](v360.md) and [web](https://x.org/a.md)")
    assert mkdocs_hooks._outside_links("[up](../index.md)", "guide/tone.md") == "[up](../index.md)"
    assert mkdocs_hooks._outside_links("![a](../../gallery/images/tones.jpg)", "guide/tone.md") == (
        "![a](../images/tones.jpg)")


def test_the_readme_test_command_is_the_one_ci_runs_and_ci_builds_the_site():
    readme = (REPO / "README.md").read_text()
    command = re.search(r'^(pip install -e "\.\[test\]" && python -m pytest[^#\n]*?)\s*(#.*)?$', readme, re.M).group(1)
    ci = (REPO / ".ci" / "run").read_text()
    assert command in ci
    assert "--durations=15" in command
    assert 'pip install -e ".[docs]"' in ci and "mkdocs build --strict" in ci
    assert len(readme.splitlines()) <= 160  # a front page; the site holds the rest
    done = subprocess.run(["bash", "-n", str(REPO / ".ci" / "run")], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


def test_the_quick_start_installs_every_system_tool_the_tests_look_for():
    from tests.conftest import SYSTEM_TOOLS

    readme = (REPO / "README.md").read_text()
    line = re.search(r"^sudo apt-get install ([^#\n]+)", readme, re.M).group(1).split()
    ci = re.search(r"apt-get install -y -qq ([^>\n]+)", (REPO / ".ci" / "run").read_text()).group(1).split()
    assert set(line) == set(ci)
    packages = {"exiftool": "libimage-exiftool-perl"}  # Debian's package of a command named otherwise
    for name, commands in SYSTEM_TOOLS.items():  # each tool the header reports comes from a package named
        assert packages.get(name) in line or any(c in line or c.replace("c++", "g++") in line for c in commands), name


def test_every_link_to_a_heading_names_one_python_markdown_gives_that_page():
    """Python-Markdown (the renderer mkdocs uses) gives each heading its id; a link to page.md#anchor must
    name one of them. A code fence closed with text on its line does not close, swallows the headings
    after it and fails here, as it fails the strict build."""
    import markdown
    pages = {p: p.read_text() for p in (REPO / "docs").rglob("*.md") if "examples" not in p.parts}
    ids: dict = {}
    for page, text in pages.items():
        html = markdown.markdown(text, extensions=["fenced_code", "toc", "tables", "attr_list", "admonition"])
        ids[page.resolve()] = set(re.findall(r'<h[1-6] id="([^"]+)"', html))
    checked = 0
    for page, text in pages.items():
        prose = re.sub(r"^```.*?^```$", "", text, flags=re.M | re.S)
        for target, anchor in re.findall(r"\]\(([^)#\s]*\.md|)#([^)\s]+)\)", prose):
            path = (page.parent / target).resolve() if target else page.resolve()
            if path in ids:
                assert anchor in ids[path], f"{page.relative_to(REPO)}: {target}#{anchor}"
                checked += 1
    assert checked >= 5
