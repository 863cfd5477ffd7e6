"""The README stays a user's page: short, free of hand-typed results, and every command in
its code blocks parses and resolves.

Results, timings and verdict counts belong in the report the pipeline writes
(``reports/<profile>/summary.md``, :mod:`thesis.report.status`), where they cannot drift
from the data. Commands are checked without running anything: ``make -n`` for make
targets, one ``snakemake -n`` per distinct set of options (several targets at once, to keep
the dry-runs few), and the CLI's own parser plus ``--help`` for ``thesis`` verbs.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from thesis import cli, registry
from thesis.claims import stats

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
MAX_LINES = 150
MAX_BYTES = 12_000
BIN = Path(sys.executable).parent

#: The only percentages the README may state: the decision rules' interval and one-sided
#: level (method constants of thesis.claims.stats, not results).
ALLOWED_PERCENT = {f"{100 * stats.CONFIDENCE:g}", f"{100 * stats.ONE_SIDED:g}"}

#: Patterns of a typed result: a percentage, a duration (a budget written "≤ N min" is a
#: rule, not a measurement), a count "k of n", a verdict count, a speed, size or factor.
RESULT_PATTERNS = {
    "percentage": re.compile(r"(\d+(?:[.,]\d+)?)\s?%"),
    "duration": re.compile(r"\b\d+(?:[.,]\d+)?\s?(?:ms|s|sec|min|minutes|h|hours|days?)\b"),
    "count": re.compile(r"\b\d+ (?:of|out of) \d+\b"),
    "verdict count": re.compile(r"\b\d+ (?:claims?|verdicts?)\b"),
    "speed, size or factor": re.compile(
        r"\b\d+(?:\.\d+)?\s?(?:m/s|m s-1|rad/s|[KMG]B)\b|\b\d+(?:\.\d+)?x\b"),
}


def hand_typed_results(text: str) -> list[str]:
    """Every match of :data:`RESULT_PATTERNS` in ``text`` that is no allowed constant:
    ``"<kind>: <context>"``."""
    found = []
    for kind, pattern in RESULT_PATTERNS.items():
        for m in pattern.finditer(text):
            before = text[max(0, m.start() - 3):m.start()]
            if kind == "percentage" and m.group(1) in ALLOWED_PERCENT:
                continue
            if kind == "duration" and ("≤" in before or "<=" in before):
                continue
            found.append(f"{kind}: ...{text[max(0, m.start() - 30):m.end() + 10]!r}...")
    return found


def code_commands(text: str) -> list[list[str]]:
    """The shell commands in the fenced code blocks of a Markdown text, each as its
    ``shlex`` tokens (comments dropped, backslash continuations joined)."""
    out = []
    for block in code_blocks(text):
        for line in block.replace("\\\n", " ").splitlines():
            tokens = shlex.split(line, comments=True)
            if tokens:
                out.append(tokens)
    return out


def code_blocks(text: str) -> list[str]:
    """The fenced code blocks of a Markdown text."""
    return re.findall(r"^```(?:bash|sh|shell|console)?\n(.*?)^```", text, re.M | re.S)


def _kind(tokens: list[str]) -> str:
    if tokens[0] == "make":
        return "make"
    if tokens[:3] == ["uv", "run", "snakemake"]:
        return "snakemake"
    if tokens[:3] == ["uv", "run", "thesis"]:
        return "thesis"
    return "unknown"


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = str(BIN) + os.pathsep + env.get("PATH", "")
    return env


def test_readme_fits_a_five_minute_read():
    text = README.read_text()
    assert len(text.splitlines()) <= MAX_LINES, f"{len(text.splitlines())} lines"
    assert len(text.encode()) <= MAX_BYTES, f"{len(text.encode())} bytes"


def test_readme_quotes_no_result():
    found = hand_typed_results(README.read_text())
    assert not found, "results belong in the generated report:\n" + "\n".join(found)


def test_the_result_patterns_catch_typed_results():
    """The checker itself: typed results are found, rules and method constants are not."""
    typed = ("took 86 min of wall time", "falls in 34 % of evaluations", "4 of 40 seeds",
             "2 claims reproduce", "walks 0.36 m/s", "68 MB", "1.1-2.6x our time",
             "(168 min of CPU)")
    for t in typed:
        assert hand_typed_results(t), t
    for ok in ("≤ 15 min on 2 CPU cores", "≤ 4 h", "its 95 % interval", "the 2.5 % test",
               "Tab. 5.3", "chapters 2 to 7", "perturb=1e-7", "≥ 3 seeds"):
        assert not hand_typed_results(ok), ok


def test_readme_commands_are_of_a_checked_kind_and_parse():
    text = README.read_text()
    commands = code_commands(text)
    assert any(c[:2] == ["make", "all"] for c in commands)
    assert any(c[:2] == ["make", "test"] for c in commands)
    unknown = [" ".join(c) for c in commands if _kind(c) == "unknown"]
    assert not unknown, f"no check for these README commands: {unknown}"
    for block in code_blocks(text):
        proc = subprocess.run(["bash", "-n"], input=block, text=True, capture_output=True)
        assert proc.returncode == 0, f"{proc.stderr}\n{block}"


@pytest.mark.slow
def test_readme_commands_resolve(capsys):
    """make targets with ``make -n``; snakemake targets with one dry-run per distinct set
    of options; ``thesis`` commands with the CLI's parser (experiment and benchmark names
    against the registry) and each verb's ``--help``."""
    commands = code_commands(README.read_text())
    for c in (c for c in commands if _kind(c) == "make"):
        proc = subprocess.run(["make", "-n", *c[1:]], cwd=ROOT, env=_env(),
                              capture_output=True, text=True, timeout=60)
        assert proc.returncode == 0, f"{' '.join(c)}:\n{proc.stderr[-2000:]}"

    groups: dict[tuple[str, ...], list[str]] = {}
    for c in (c[3:] for c in commands if _kind(c) == "snakemake"):
        first_option = next((i for i, t in enumerate(c) if t.startswith("-")), len(c))
        groups.setdefault(tuple(c[first_option:]), []).extend(c[:first_option])
    assert groups
    for options, targets in groups.items():
        proc = subprocess.run([str(BIN / "snakemake"), *targets, "-n", *options], cwd=ROOT,
                              env=_env(), capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, (f"snakemake {' '.join(targets)} -n {' '.join(options)}"
                                      f":\n{proc.stderr[-3000:]}")

    verbs = set()
    parser = cli.build_parser()
    for c in (c[3:] for c in commands if _kind(c) == "thesis"):
        args = parser.parse_args(c)  # exits (fails the test) on an unknown verb or option
        verbs.add(args.command)
        if args.command == "run":
            assert args.key in registry.EXPERIMENTS, args.key
        if args.command == "bench":
            assert args.name in registry.BENCHMARKS, args.name
    for verb in sorted(verbs):
        with pytest.raises(SystemExit) as done:
            parser.parse_args([verb, "--help"])
        assert done.value.code == 0, verb
    assert f"usage: thesis {verb}" in capsys.readouterr().out
    # the entry point the commands go through (`uv run thesis` is `python -m thesis`)
    proc = subprocess.run([sys.executable, "-m", "thesis", "--help"], cwd=ROOT, env=_env(),
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0 and all(v in proc.stdout for v in verbs), proc.stderr[-2000:]
