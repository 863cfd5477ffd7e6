"""A damaged result or input file is named in one line, with its role and the command that
remakes it, and costs nothing else: ``thesis check`` and ``thesis report``
decide and render every other chapter as with the intact file and exit non-zero;
``thesis run`` refuses a damaged ``--input`` before it starts and writes nothing.

Every fixture is a small dataset written by the test (the claims tests' fabricated
chapter-3 and chapter-7 results); no pipeline runs."""

from __future__ import annotations

import inspect
import json
import re
import textwrap
from datetime import datetime, timezone
from pathlib import Path

import h5py
import numpy as np
import pytest
import xarray as xr

from tests.claims import test_ch3 as ch3_data
from tests.claims import test_ch7 as ch7_data
from thesis import cli, registry, store
from thesis.claims import calibration
from thesis.errors import DamagedFileError, MissingInputError

ROOT = Path(__file__).resolve().parents[2]
DAMAGED_KEY = "ch3/fig3_4"
DAMAGES = ("truncated", "empty", "text", "other_artifact")


def _stamped(ds: xr.Dataset, key: str) -> xr.Dataset:
    """``ds`` with what the store requires of a result (thesis_ref, seeds, units)."""
    ds = ds.copy()
    ds.attrs.setdefault("thesis_ref", f"test {key}")
    ds.attrs.setdefault("seeds", [0])
    for name in ds.variables:
        if name in ds.data_vars or ds[name].dims != (name,):
            ds[name].attrs.setdefault("units", "1")
            ds[name].attrs.setdefault("long_name", name)
    return ds


def _put(root: Path, runs: str, key: str, ds: xr.Dataset, **attrs) -> Path:
    return store.write_dataset(_stamped(ds.assign_attrs(**attrs), key),
                               store.result_path(runs, key, root), profile="smoke",
                               experiment=key, config_slice={}, wall_seconds=1.0,
                               started=datetime(2026, 1, 1, tzinfo=timezone.utc))


def _results(root: Path) -> dict[str, Path]:
    """Chapter 3's and chapter 7's results, each feeding claims that are decided and
    tables the report renders."""
    made = {"ch3/fig3_4": ch3_data.fig3_4(),
            "ch3/robustness": ch3_data.robustness([0.9, 0.8, 0.85]),
            "ch7/table7_1": ch7_data.table7_1()}
    return {k: _put(root, "smoke", k, ds) for k, ds in made.items()}


def _damage(path: Path, how: str, root: Path) -> None:
    """Damage ``path`` as a full disk, a cut copy or a mix-up would."""
    if how == "truncated":
        data = path.read_bytes()
        path.write_bytes(data[: len(data) // 2])
    elif how == "empty":
        path.write_bytes(b"")
    elif how == "text":
        path.write_text("Traceback (most recent call last):\n  disk full\n")
    elif how == "other_artifact":  # another artifact's dataset under this name
        other = _put(root / "elsewhere", "smoke", "ch7/ball", ch7_data.ball())
        path.write_bytes(other.read_bytes())
    else:
        raise ValueError(how)


@pytest.fixture(autouse=True)
def _fast_power(monkeypatch):
    """``thesis check`` writes the rules' power table too; a stub keeps the test fast."""
    monkeypatch.setattr(calibration, "power_table",
                        lambda: {"nominal": 0.025, "reps": 1, "rows": []})


def _check(root: Path, capsys) -> tuple[int, dict, str]:
    rc = cli.main(["check", "--profile", "smoke", "--results", str(root)])
    err = capsys.readouterr().err
    return rc, json.loads((root / "smoke" / "claims.json").read_text()), err


def _no_temporaries(root: Path) -> None:
    left = [p for p in root.rglob(".*") if p.is_file()]
    assert left == [], f"half-written files left: {left}"


@pytest.mark.parametrize("how", DAMAGES)
def test_open_result_names_the_file_its_role_the_cause_and_the_remaking_command(
        tmp_path, how):
    path = _results(tmp_path)[DAMAGED_KEY]
    _damage(path, how, tmp_path)
    with pytest.raises(DamagedFileError) as info:
        store.open_result(path, DAMAGED_KEY, runs="smoke")
    msg = str(info.value)
    assert "\n" not in msg
    assert msg.startswith(f"{path} (result ch3/fig3_4 of chapter 3, results/smoke/)")
    assert msg.endswith("uv run snakemake results/smoke/ch3/fig3_4.nc --force "
                        "--config profile=smoke --cores 2")
    cause = {"truncated": r"truncated: [\d,]+ of its [\d,]+ bytes are on disk",
             "empty": r"empty \(0 bytes\)",
             "text": r"not an HDF5/netCDF-4 file \(\d+ bytes beginning 'Traceback",
             "other_artifact": r"holds the result of ch7/ball .*not of ch3/fig3_4"}[how]
    assert re.search(cause, info.value.cause), info.value.cause


@pytest.mark.parametrize("how", DAMAGES)
def test_check_decides_every_other_claim_as_with_the_intact_file(tmp_path, capsys, how):
    paths = _results(tmp_path)
    rc, intact, err = _check(tmp_path, capsys)
    assert rc == 0 and err == "" and intact["damaged"] == []
    _damage(paths[DAMAGED_KEY], how, tmp_path)
    rc, got, err = _check(tmp_path, capsys)

    assert rc == cli.EXIT_DAMAGED
    line = err.strip()
    assert "\n" not in line and str(paths[DAMAGED_KEY]) in line
    assert "uv run snakemake results/smoke/ch3/fig3_4.nc --force" in line
    assert [d["path"] for d in got["damaged"]] == [str(paths[DAMAGED_KEY])]
    before = {c["id"]: c for c in intact["claims"]}
    needing = [c for c in got["claims"] if DAMAGED_KEY in c["requires"]]
    others = [c for c in got["claims"] if DAMAGED_KEY not in c["requires"]]
    assert needing and others
    for c in needing:  # not decided, and saying why
        assert c["status"] == "not_run"
        assert c["detail"].startswith(f"unreadable result: {paths[DAMAGED_KEY]} (")
        assert [u["key"] for u in c["unreadable"]] == [DAMAGED_KEY]
    assert any(before[c["id"]]["status"] != "not_run" for c in needing)
    for c in others:  # every other verdict exactly as with the intact file
        assert c == before[c["id"]], c["id"]
    decided = {c["chapter"] for c in others if c["status"] != "not_run"}
    assert {3, 7} <= decided  # ch3's other results and ch7's are still decided
    _no_temporaries(tmp_path)


def test_check_with_a_damaged_twin_decides_everything_and_names_it(tmp_path, capsys):
    _results(tmp_path)
    twin = _put(tmp_path, "smoke-perturbed", "ch7/ball", ch7_data.ball(),
                perturbation_relative=1e-6)
    damaged = _put(tmp_path, "smoke-perturbed", "ch3/fig3_4", ch3_data.fig3_4())
    _damage(damaged, "truncated", tmp_path)
    rc, got, err = _check(tmp_path, capsys)
    assert rc == cli.EXIT_DAMAGED and twin.exists()
    assert "results/smoke-perturbed/ch3/fig3_4.nc --force --config profile=smoke " \
           "perturb=1e-06 --cores 2" in err
    assert got["twin_runs"] == ["ch7/ball"]
    assert not any(c.get("unreadable") for c in got["claims"])  # the profile's own intact


def _section(summary: str, title: str) -> str:
    return summary.split(f"\n## {title}\n", 1)[1].split("\n## ", 1)[0]


def _intact_report(tmp_path, capsys):
    """(results root, report dir, result paths, report args, the intact summary): the
    fabricated results decided and reported once before anything is damaged."""
    results, out = tmp_path / "results", tmp_path / "reports"
    paths = _results(results)
    _check(results, capsys)
    args = ["report", "--profile", "smoke", "--results", str(results), "--outdir", str(out)]
    assert cli.main(args) == 0
    return results, out, paths, args, (out / "summary.md").read_text()


@pytest.mark.parametrize("how", DAMAGES)
def test_report_names_the_damaged_file_first_and_renders_the_rest(tmp_path, capsys, how):
    results, out, paths, args, intact = _intact_report(tmp_path, capsys)
    _damage(paths[DAMAGED_KEY], how, results)
    _check(results, capsys)

    rc = cli.main(args)
    err = capsys.readouterr().err.strip()
    assert rc == cli.EXIT_DAMAGED
    assert "\n" not in err and str(paths[DAMAGED_KEY]) in err
    assert "snakemake results/smoke/ch3/fig3_4.nc" in err
    page = (out / "index.html").read_text()
    summary = (out / "summary.md").read_text()
    first_chapter = page.index('<h2 id="ch2">')
    assert page.index('id="damaged"') < first_chapter
    assert page.index(str(paths[DAMAGED_KEY])) < first_chapter
    assert summary.index("Damaged result files: 1") < summary.index("\n## ")
    from thesis.report.chapters import CHAPTERS

    assert _section(summary, CHAPTERS["ch7"]) == _section(intact, CHAPTERS["ch7"])
    assert _section(summary, CHAPTERS["ch3"]) != _section(intact, CHAPTERS["ch3"])
    _no_temporaries(tmp_path)


FAKE = textwrap.dedent('''
    import numpy as np
    import xarray as xr

    def uses_teacher(ctx):
        src = xr.load_dataset(ctx.input("teacher"))
        v = xr.DataArray([float(src["iterations"].mean())], dims="seed", coords={"seed": [0]},
                         attrs={"units": "1", "long_name": "teacher iterations"})
        return xr.Dataset({"x": v}, attrs={"thesis_ref": "Fig. 6.4", "seeds": [0]})

    def uses_recordings(ctx):
        import h5py
        with h5py.File(ctx.input("recordings"), "r") as f:
            n = float(f["signals"].shape[0])
        v = xr.DataArray([n], dims="seed", coords={"seed": [0]},
                         attrs={"units": "1", "long_name": "samples"})
        return xr.Dataset({"n": v}, attrs={"thesis_ref": "Tab. 5.3", "seeds": [0]})
''')


@pytest.fixture
def fake_runs(tmp_path, monkeypatch):
    """ch6/trot and ch5/table5_3 replaced by experiments that read their input as the
    real ones do (the check comes before the experiment, whatever it is)."""
    (tmp_path / "fake_damaged.py").write_text(FAKE)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(registry.EXPERIMENTS, "ch6/trot", "fake_damaged:uses_teacher")
    monkeypatch.setitem(registry.EXPERIMENTS, "ch5/table5_3", "fake_damaged:uses_recordings")
    return tmp_path


def _run(args, capsys) -> tuple[int, str]:
    rc = cli.main(["run", *args, "--profile", "smoke"])
    return rc, capsys.readouterr().err.strip()


@pytest.mark.parametrize("how", DAMAGES)
def test_run_refuses_a_damaged_input_in_one_line_and_writes_nothing(fake_runs, capsys, how):
    root = fake_runs / "results"
    teacher = _put(root, "smoke", "ch6/teacher", ch7_data.ball())
    out = fake_runs / "out" / "trot.nc"
    rc, err = _run(["ch6/trot", "--input", f"teacher={teacher}", "--output", str(out)], capsys)
    assert rc == 0 and out.exists()  # the intact input runs
    out.unlink()
    _damage(teacher, how, fake_runs)
    rc, err = _run(["ch6/trot", "--input", f"teacher={teacher}", "--output", str(out)], capsys)
    assert rc == cli.EXIT_DAMAGED
    assert "\n" not in err
    assert err.startswith(f"thesis: {teacher} (input 'teacher' of experiment ch6/trot)")
    assert err.endswith("uv run snakemake results/smoke/ch6/teacher.nc --force "
                        "--config profile=smoke --cores 2")
    assert list(out.parent.iterdir()) == []  # no result, no temporary file
    _no_temporaries(fake_runs)


def test_run_names_the_input_a_file_outside_the_layout_stands_for(fake_runs, capsys):
    stray, out = fake_runs / "my_teacher.nc", fake_runs / "trot.nc"
    stray.write_bytes(b"")
    rc, err = _run(["ch6/trot", "--input", f"teacher={stray}", "--output", str(out)], capsys)
    assert rc == cli.EXIT_DAMAGED and "empty (0 bytes)" in err
    assert "snakemake results/smoke/ch6/teacher.nc" in err
    rc, err = _run(["ch6/trot", "--input", f"teacher={fake_runs / 'absent.nc'}",
                    "--output", str(out)], capsys)
    assert rc == cli.EXIT_DAMAGED
    assert "absent.nc (input 'teacher' of experiment ch6/trot) does not exist" in err
    assert not out.exists()


def _recordings(path: Path, thesis_ref: str = "§5.3.1") -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    with h5py.File(path, "w") as f:
        f.create_dataset("signals", data=np.zeros((50, 3)))
        f.attrs["thesis_ref"] = thesis_ref
    return path


@pytest.mark.parametrize("how", [*DAMAGES, "foreign_h5"])
def test_a_damaged_generated_input_names_the_data_target(fake_runs, capsys, how):
    data = _recordings(fake_runs / "data" / "synthetic" / "puppy" / "smoke.h5")
    out = fake_runs / "t53.nc"
    rc, _ = _run(["ch5/table5_3", "--input", f"recordings={data}", "--output", str(out)],
                 capsys)
    assert rc == 0 and out.exists()
    out.unlink()
    if how == "foreign_h5":  # another generator's file
        _recordings(data, thesis_ref="§2.5")
    else:
        _damage(data, how, fake_runs)
    rc, err = _run(["ch5/table5_3", "--input", f"recordings={data}", "--output", str(out)],
                   capsys)
    assert rc == cli.EXIT_DAMAGED and "\n" not in err
    assert f"{data} (input 'recordings' of experiment ch5/table5_3)" in err
    assert err.endswith("uv run snakemake data/synthetic/puppy/smoke.h5 --force "
                        "--config profile=smoke --cores 2")
    if how in ("foreign_h5", "other_artifact"):
        assert "wrong content" in err
    assert not out.exists()


def test_input_producers_follow_the_rules_names():
    assert store.input_producer("ch6/trot", "teacher", "default") == (
        "ch6/teacher", "results/default/ch6/teacher.nc")
    assert store.input_producer("ch6/teacher", "table3_1", "smoke") == (
        "ch3/table3_1", "results/smoke/ch3/table3_1.nc")
    assert store.input_producer("ch2/table2_2", "rnn_spn_seed2", "default") == (
        "ch2/table2_2_rnn_spn", "results/default/ch2/parts/table2_2_rnn_spn_seed2.nc")
    assert store.input_producer("ch2/table2_2_ffn_spn", "data", "default-native") == (
        "ch2/cluttered_mnist", "data/synthetic/cluttered_mnist/default-native.h5")
    assert store.input_producer("ch7/ball", "nothing_like_it", "default") == (None, None)


def test_generated_inputs_match_the_workflow_and_their_generators():
    smk = "".join(p.read_text() for p in (ROOT / "workflow" / "rules").glob("*.smk"))
    assert set(re.findall(r'data_path\("(\w+)"\)', smk)) == {
        name for name, _ in store.GENERATED_INPUTS.values()}
    for key, (_, ref) in store.GENERATED_INPUTS.items():
        src = inspect.getsource(registry.resolve(key))
        assert f'"thesis_ref": "{ref}"' in src, key


def test_load_results_raises_the_one_line_error(tmp_path):
    path = _results(tmp_path)[DAMAGED_KEY]
    _damage(path, "empty", tmp_path)
    with pytest.raises(DamagedFileError, match=r"fig3_4\.nc \(result ch3/fig3_4 .*empty"):
        store.load_results("smoke", tmp_path)
    with pytest.raises(MissingInputError, match="does not exist"):
        store.check_input("ch6/trot", "teacher", tmp_path / "nope.nc")


# the CLI's options before its command: --perturb REL, --config-json '{...}' (overrides)
GLOBAL_OPTS = r"(?:--[\w-]+ (?:'[^']*'|\S+) )*"


@pytest.mark.slow
def test_every_input_the_rules_pass_is_what_its_check_expects():
    """Every ``--input name=path`` of the planned jobs (smoke, with chapter 3's screen of
    teachers and Tab. 5.3's variants): the result or generated input the check expects
    for ``name`` is the one the path holds, and the remaking target is the path itself;
    and every result ``results/smoke/<ch>/<artifact>.nc`` is written by experiment
    ``<ch>/<artifact>``; so the checks refuse no intact file of the pipeline."""
    from tests.pipeline.conftest import snakemake

    proc = snakemake("all", "ch5_variants", "--forceall", "-n", "-p", "--cores", "1",
                     "--config", "profile=smoke", 'ch6={"teacher": {"source": "screen"}}',
                     timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]
    seen, written = set(), 0
    for line in (proc.stdout + proc.stderr).splitlines():
        m = re.search(rf"-m thesis {GLOBAL_OPTS}(run|bench) (\S+) .*--output (\S+)", line)
        if m and re.fullmatch(r"results/smoke/\w+/\w+\.nc", m[3]):
            key = registry.BENCHMARKS[m[2]] if m[1] == "bench" else m[2]
            assert m[3] == f"results/smoke/{key}.nc", (key, m[3])
            written += 1
        m = re.search(rf"-m thesis {GLOBAL_OPTS}run (\S+)", line)
        for name, path in re.findall(r"--input (\w+)=(\S+)", line) if m else ():
            want, target = store.input_producer(m[1], name, "smoke")
            assert want is not None and target == path, (m[1], name, path, want, target)
            seen.add(want)
    assert {"ch3/table3_1", "ch6/teacher", "ch4/flat", "ch2/table2_2_ffn_spn",
            "ch2/cluttered_mnist", "ch5/puppy_recordings"} <= seen
    assert written > 40


def test_a_generated_input_passed_for_a_result_is_refused(fake_runs, capsys, tmp_path):
    """An HDF5 file xarray can read but ``thesis run`` did not write (no ``experiment``)."""
    data = _recordings(fake_runs / "data" / "synthetic" / "puppy" / "smoke.h5")
    out = fake_runs / "trot.nc"
    rc, err = _run(["ch6/trot", "--input", f"teacher={data}", "--output", str(out)], capsys)
    assert rc == cli.EXIT_DAMAGED and "attribute 'experiment' is missing" in err
    assert "snakemake results/smoke/ch6/teacher.nc" in err and not out.exists()


def test_report_figures_of_the_damaged_chapter_exit_nonzero_the_others_not(tmp_path, capsys):
    results, out = tmp_path / "results", tmp_path / "reports"
    _damage(_results(results)[DAMAGED_KEY], "truncated", results)
    args = ["report", "--profile", "smoke", "--results", str(results), "--outdir", str(out)]
    assert cli.main([*args, "--figures", "ch7"]) == 0
    assert cli.main([*args, "--figures", "ch3"]) == cli.EXIT_DAMAGED
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "ch3/fig3_4.nc (truncated" in err
    assert (out / "figures" / "ch3" / "manifest.json").exists()


def test_report_sets_aside_a_readable_result_lacking_a_variable_its_tables_read(
        tmp_path, capsys):
    """A result that opens but lacks a variable a chapter's tables read (written by other
    code, or cut short) is set aside like a damaged file: named with the variable and its
    remaking command at the top of the page, its chapter rendered without it, every other
    chapter as with the intact file, exit non-zero. Another KeyError of the report's code
    is not hidden."""
    results, out, paths, args, intact = _intact_report(tmp_path, capsys)
    path = paths["ch7/table7_1"]
    ds = xr.load_dataset(path)
    assert "seconds" in ds and len(ds.data_vars) > 1
    cut = ds.drop_vars("seconds")
    path.unlink()
    cut.to_netcdf(path, engine="h5netcdf")
    from thesis.report.chapters import CHAPTERS
    from thesis.report.chapters import ch7 as report_ch7

    real = report_ch7.tables

    def reads_seconds(res):  # the chapter's tables, reading the variable as a table does
        if "ch7/table7_1" in res:
            res["ch7/table7_1"]["seconds"]
        return real(res)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(report_ch7, "tables", reads_seconds)
        rc = cli.main(args)
        err = capsys.readouterr().err.strip()
        assert rc == cli.EXIT_DAMAGED
        assert "\n" not in err and str(path) in err and "lacks the variable 'seconds'" in err
        assert "snakemake results/smoke/ch7/table7_1.nc" in err
        page = (out / "index.html").read_text()
        summary = (out / "summary.md").read_text()
        assert page.index('id="damaged"') < page.index('<h2 id="ch2">')
        assert "lacks the variable" in summary.split("\n## ")[0]
        assert _section(summary, CHAPTERS["ch3"]) == _section(intact, CHAPTERS["ch3"])

        def broken(res):  # a defect of the report's code: no result lacks 'nowhere'
            raise KeyError("No variable named 'nowhere'. Variables on the dataset include []")

        mp.setattr(report_ch7, "tables", broken)
        rc = cli.main(args)
        err = capsys.readouterr().err
        assert rc not in (0, cli.EXIT_DAMAGED) and "nowhere" in err and "lacks" not in err
    _no_temporaries(tmp_path)
