"""The files a user reads before the code: CITATION.cff is valid Citation File
Format 1.2.0 (its schema's required keys, key sets and value rules, checked
here without cffconvert), CHANGELOG.md has the version pyproject declares,
and no README, doc or help text speaks of the project's internal history."""
from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# Citation File Format 1.2.0 (schema.json of citation-file-format 1.2.0): the
# root's properties (additionalProperties false) and required keys
CFF_ROOT_KEYS = {"abstract", "authors", "cff-version", "commit", "contact", "date-released", "doi",
                 "identifiers", "keywords", "license", "license-url", "message", "preferred-citation",
                 "references", "repository", "repository-artifact", "repository-code", "title", "type", "url",
                 "version"}
CFF_ROOT_REQUIRED = {"authors", "cff-version", "message", "title"}
CFF_PERSON_KEYS = {"address", "affiliation", "alias", "city", "country", "email", "family-names", "fax",
                   "given-names", "name-particle", "name-suffix", "orcid", "post-code", "region", "tel", "website"}
CFF_ENTITY_KEYS = {"address", "alias", "city", "country", "date-end", "date-start", "email", "fax", "location",
                   "name", "orcid", "post-code", "region", "tel", "website"}
CFF_REFERENCE_REQUIRED = {"authors", "title", "type"}
CFF_REFERENCE_KEYS = {
    "abbreviation", "abstract", "authors", "collection-doi", "collection-title", "collection-type", "commit",
    "conference", "contact", "copyright", "data-type", "database", "database-provider", "date-accessed",
    "date-downloaded", "date-published", "date-released", "department", "doi", "edition", "editors",
    "editors-series", "end", "entry", "filename", "format", "identifiers", "institution", "isbn", "issn", "issue",
    "issue-date", "issue-title", "journal", "keywords", "languages", "license", "license-url", "loc-end",
    "loc-start", "location", "medium", "month", "nihmsid", "notes", "number", "number-volumes", "pages",
    "patent-states", "pmcid", "publisher", "recipients", "repository", "repository-artifact", "repository-code",
    "scope", "section", "senders", "start", "status", "term", "thesis-type", "title", "translators", "type", "url",
    "version", "volume", "volume-title", "year", "year-original"}
CFF_REFERENCE_TYPES = {
    "art", "article", "audiovisual", "bill", "blog", "book", "catalogue", "conference-paper", "conference", "data",
    "database", "dictionary", "edited-work", "encyclopedia", "film-broadcast", "generic", "government-document",
    "grant", "hearing", "historical-work", "legal-case", "legal-rule", "magazine-article", "manual", "map",
    "multimedia", "music", "newspaper-article", "pamphlet", "patent", "personal-communication", "proceedings",
    "report", "serial", "slides", "software-code", "software-container", "software-executable",
    "software-virtual-machine", "software", "sound-recording", "standard", "statute", "thesis", "unpublished",
    "video", "website"}
DOI = re.compile(r"^10\.\d{4,9}(\.\d+)?/[A-Za-z0-9:/_;\-\.\(\)\[\]\\]+$")
URL = re.compile(r"^(https|http|ftp|sftp)://.+")


def _nonempty_str(value, where):
    assert isinstance(value, str) and value, f"{where}: a non-empty string"


def _persons(items, where):
    assert isinstance(items, list) and items, f"{where}: a non-empty list"
    assert len({repr(sorted(p.items())) for p in items}) == len(items), f"{where}: items must be unique"
    for k, p in enumerate(items):
        assert isinstance(p, dict) and p, f"{where}[{k}]: a person or an entity"
        if "name" in p:                                    # an entity
            assert set(p) <= CFF_ENTITY_KEYS, f"{where}[{k}]: keys {set(p) - CFF_ENTITY_KEYS}"
            _nonempty_str(p["name"], f"{where}[{k}].name")
        else:
            assert set(p) <= CFF_PERSON_KEYS, f"{where}[{k}]: keys {set(p) - CFF_PERSON_KEYS}"
            assert "family-names" in p or "given-names" in p or "alias" in p, f"{where}[{k}]: no name"
        for key, v in p.items():
            _nonempty_str(v, f"{where}[{k}].{key}")


def _keywords(items, where):
    assert isinstance(items, list) and items and len(set(items)) == len(items), where
    for v in items:
        _nonempty_str(v, where)


def validate_cff(doc: dict) -> None:
    """Raise AssertionError where doc breaks the CFF 1.2.0 schema (the keys this
    project uses are checked to their value rules; any other key must exist)."""
    assert isinstance(doc, dict)
    assert CFF_ROOT_REQUIRED <= set(doc), f"missing {CFF_ROOT_REQUIRED - set(doc)}"
    assert set(doc) <= CFF_ROOT_KEYS, f"unknown keys {set(doc) - CFF_ROOT_KEYS}"
    assert doc["cff-version"] == "1.2.0"
    _nonempty_str(doc["message"], "message")
    _nonempty_str(doc["title"], "title")
    _persons(doc["authors"], "authors")
    if "type" in doc:
        assert doc["type"] in ("software", "dataset")
    if "version" in doc:
        assert isinstance(doc["version"], (str, int, float)) and str(doc["version"])
    if "keywords" in doc:
        _keywords(doc["keywords"], "keywords")
    if "license" in doc:
        assert doc["license"] in ("MIT", "Apache-2.0", "BSD-3-Clause", "GPL-3.0-or-later"), doc["license"]
    if "doi" in doc:
        assert DOI.match(doc["doi"])
    for key in ("url", "repository-code", "repository", "repository-artifact", "license-url"):
        if key in doc:
            assert URL.match(doc[key]), key
    if "date-released" in doc:
        assert re.match(r"^[0-9]{4}-(0[1-9]|1[012])-(0[1-9]|[12][0-9]|3[01])$", str(doc["date-released"]))
    for ref in ([doc["preferred-citation"]] if "preferred-citation" in doc else []) + doc.get("references", []):
        assert CFF_REFERENCE_REQUIRED <= set(ref), f"reference missing {CFF_REFERENCE_REQUIRED - set(ref)}"
        assert set(ref) <= CFF_REFERENCE_KEYS, f"reference keys {set(ref) - CFF_REFERENCE_KEYS}"
        assert ref["type"] in CFF_REFERENCE_TYPES, ref["type"]
        _nonempty_str(ref["title"], "reference title")
        _persons(ref["authors"], "reference authors")
        if "keywords" in ref:
            _keywords(ref["keywords"], "reference keywords")
        if "doi" in ref:
            assert DOI.match(ref["doi"])
        for key in ("year", "volume", "start", "end", "month"):
            if key in ref:
                assert isinstance(ref[key], int) and not isinstance(ref[key], bool), key


def _pyproject_version() -> str:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]


def test_citation_cff_is_valid_cff_1_2_and_cites_the_paper():
    yaml = pytest.importorskip("yaml")
    doc = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    validate_cff(doc)
    assert str(doc["version"]) == _pyproject_version()
    ref = doc["preferred-citation"]
    assert "multiple friction pendulum devices" in ref["title"].lower()
    assert [a["family-names"] for a in ref["authors"]] == ["Bianco", "Monti", "Belfiore"]


@pytest.mark.parametrize("broken", [
    {"cff-version": "1.1.0"},
    {"title": ""},
    {"authors": []},
    {"colour": "blue"},
    {"preferred-citation": {"title": "x", "authors": [{"family-names": "A"}], "type": "paper"}},
    {"preferred-citation": {"title": "x", "type": "article"}},
    {"authors": [{"family-names": "A", "nickname": "a"}]},
])
def test_the_cff_check_can_fail(broken):
    """The validator refuses what the schema refuses (it is not a test that cannot fail)."""
    doc = {"cff-version": "1.2.0", "message": "m", "title": "t", "authors": [{"name": "x"}]}
    doc.update(broken)
    with pytest.raises(AssertionError):
        validate_cff(doc)


def test_changelog_has_the_declared_version():
    text = (ROOT / "CHANGELOG.md").read_text()
    heads = re.findall(r"^## (.+)$", text, flags=re.M)
    assert heads[0] == "Unreleased"
    versions = [h.split()[0] for h in heads[1:]]
    assert versions[0] == _pyproject_version()
    assert "0.1.0" in versions
    import fpd
    assert fpd.__version__ == _pyproject_version()


# -- no internal history in what users read --------------------------------------------
HISTORY = re.compile(r"\bwaves?\b(?! ?(?:form|speed|length|number|equation|propagation))|\bissues? #?\d+|\bi\d{1,2} merge\b",
                     flags=re.I)


def _user_texts():
    files = [ROOT / "README.md", ROOT / "CHANGELOG.md"] + sorted((ROOT / "docs").glob("*.md"))
    for f in files:
        yield f.relative_to(ROOT).as_posix(), f.read_text(encoding="utf-8")
    # help texts: every command's --help, the scene-key descriptions, the package's docstrings
    import contextlib
    import io

    from fpd.frontends import cli, descriptions
    commands = ["", "run", "render", "compare", "converge", "stability", "sweep", "map", "scenes", "reference",
                "check"]
    for c in commands:
        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
            with contextlib.suppress(SystemExit):
                cli.main(([c] if c else []) + ["--help"])
        yield f"fpd {c} --help", out.getvalue()
    for name in ("SCENE", "COLUMNS", "SUMMARY"):
        table = getattr(descriptions, name, {})
        yield f"descriptions.{name}", "\n".join(str(v) for v in table.values())
    import fpd
    from fpd.frontends import api
    yield "fpd docstring", fpd.__doc__
    yield "fpd.frontends.api docstrings", "\n".join(
        [api.__doc__ or ""] + [getattr(api, n).__doc__ or "" for n in api.__all__])


def test_no_internal_history_in_readme_docs_or_help():
    """README, docs and help describe the product, not how it was built: no
    'wave', no 'issue 13' (a user cannot resolve either)."""
    bad = []
    for where, text in _user_texts():
        for m in HISTORY.finditer(text):
            line = text.count("\n", 0, m.start()) + 1
            bad.append(f"{where}:{line}: {text[max(0, m.start() - 30):m.end() + 30]!r}")
    assert not bad, "\n".join(bad)


def test_history_pattern_catches_what_it_should():
    for s in ("after wave 2", "Wave 1 met", "(issue 13)", "issues 7", "issue #4"):
        assert HISTORY.search(s), s
    for s in ("a shear wave speed", "tissue 13", "the waveform"):
        assert not HISTORY.search(s), s


def test_readme_setup_makes_a_venv_and_gives_one_compile_time():
    text = (ROOT / "README.md").read_text()
    setup = text[text.index("## Set-up"):text.index("\n## ", text.index("## Set-up") + 5)]
    cmds = [line.strip() for line in setup.splitlines() if line.startswith("    python3")]
    assert len(cmds) == 2
    for c in cmds:
        assert c.startswith("python3 -m venv .venv && . .venv/bin/activate && python3 -m pip install -e ")
    # the first compile: one number wherever README, the docs or the notice state it
    from fpd import jitcache
    stated = set(re.findall(r"compil\w*[^.;]{0,60}?about (\d+) s", jitcache.NOTICE))
    for f in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        body = f.read_text().replace("\n", " ")
        stated |= set(re.findall(r"compil\w* (?:them )?once[^.;]{0,20}?\(?(?:~|about )(\d+(?:-\d+)?) s", body))
        assert not re.search(r"compil\w*[^.;]{0,40}?~\d+-\d+ s", body), f
    assert stated == {"15"}, stated
