"""The CLI runs a registered experiment, stamps provenance, and refuses to write NaN runs."""

from __future__ import annotations

import textwrap

import pytest

from thesis import cli, registry, store

FAKE = textwrap.dedent('''
    import numpy as np
    import xarray as xr
    from thesis.errors import SimulationDiverged

    def good(ctx):
        seeds = [0, 1]
        v = xr.DataArray(np.array([1.0, 2.0]) * ctx.root_seed, dims="seed",
                         coords={"seed": seeds},
                         attrs={"units": "m", "long_name": "distance"})
        return xr.Dataset({"distance": v}, attrs={"thesis_ref": "Tab. 0.0", "seeds": seeds})

    def diverges(ctx):
        raise SimulationDiverged(ctx.key, seed=1, step=42, what="body_pos")

    def widths(ctx):
        seeds = [int(s) for s in ctx.config["seeds"]]
        v = xr.DataArray([float(ctx.config["ffn_spn"]["cls_dense"])] * len(seeds), dims="seed",
                         coords={"seed": seeds}, attrs={"units": "1", "long_name": "width"})
        return xr.Dataset({"width": v}, attrs={"thesis_ref": "Tab. 2.1", "seeds": seeds})

    def sees_perturbation(ctx):
        from thesis.physics import perturbation
        v = xr.DataArray([perturbation.relative()], dims="seed", coords={"seed": [0]},
                         attrs={"units": "1", "long_name": "relative perturbation seen"})
        return xr.Dataset({"seen": v}, attrs={"thesis_ref": "Tab. 0.0", "seeds": [0]})

    def generator(ctx):
        from thesis.store import atomic_path
        with atomic_path(ctx.output) as tmp:
            tmp.write_text("data")
''')


@pytest.fixture
def fake_registry(tmp_path, monkeypatch):
    (tmp_path / "fake_experiments.py").write_text(FAKE)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(registry.EXPERIMENTS, "ch9/good", "fake_experiments:good")
    monkeypatch.setitem(registry.EXPERIMENTS, "ch9/diverges", "fake_experiments:diverges")
    monkeypatch.setitem(registry.EXPERIMENTS, "ch9/gen", "fake_experiments:generator")
    monkeypatch.setitem(registry.EXPERIMENTS, "ch9/sees", "fake_experiments:sees_perturbation")
    monkeypatch.setitem(registry.EXPERIMENTS, "ch2/widths", "fake_experiments:widths")
    monkeypatch.setitem(registry.BENCHMARKS, "fake", "ch9/good")
    monkeypatch.setenv("XLA_FLAGS", "--xla_force_host_platform_device_count=2")
    return tmp_path


def test_run_writes_result_with_provenance(fake_registry, tmp_path):
    out = tmp_path / "out" / "good.nc"
    rc = cli.main(["run", "ch9/good", "--profile", "smoke", "--output", str(out),
                   "--set", "root_seed=3"])
    assert rc == 0
    ds = store.read_dataset(out)
    assert ds["distance"].values.tolist() == [3.0, 6.0]
    assert ds.attrs["experiment"] == "ch9/good"
    assert ds.attrs["profile"] == "smoke"
    assert '"root_seed":3' in ds.attrs["config_json"]


def test_bench_dispatches_to_registered_benchmark(fake_registry, tmp_path):
    out = tmp_path / "b.nc"
    assert cli.main(["bench", "fake", "--profile", "smoke", "--output", str(out)]) == 0
    assert store.read_dataset(out).attrs["experiment"] == "ch9/good"


def test_nan_run_exits_nonzero_names_seed_and_step_and_writes_nothing(
        fake_registry, tmp_path, capsys):
    out = tmp_path / "bad.nc"
    rc = cli.main(["run", "ch9/diverges", "--profile", "smoke", "--output", str(out)])
    assert rc == 3
    err = capsys.readouterr().err
    assert "ch9/diverges" in err and "seed=1" in err and "step=42" in err
    assert not out.exists()


def test_generator_writes_its_output(fake_registry, tmp_path):
    out = tmp_path / "d" / "x.h5"
    assert cli.main(["run", "ch9/gen", "--profile", "smoke", "--output", str(out)]) == 0
    assert out.read_text() == "data"


def test_unknown_experiment_and_bad_config_are_clear(fake_registry, tmp_path, capsys):
    assert cli.main(["run", "ch9/nope", "--profile", "smoke"]) == 2
    assert "unknown experiment 'ch9/nope'" in capsys.readouterr().err
    assert cli.main(["run", "ch9/good", "--profile", "smoke", "--output",
                     str(tmp_path / "x.nc"), "--set", "ch2.bogus=1"]) == 2
    assert "ch2.bogus" in capsys.readouterr().err
    assert not (tmp_path / "x.nc").exists()


def test_perturbed_twin_run_goes_beside_the_profile(fake_registry, tmp_path, monkeypatch,
                                                    capsys):
    """``thesis --perturb REL run``: the experiment runs under the perturbation (and only
    it: the size is back to 0 after), its default output is under
    results/<profile>-perturbed/ and records the size; an out-of-range size is refused."""
    from thesis.physics import perturbation

    monkeypatch.chdir(tmp_path)
    assert cli.main(["--perturb", "1e-7", "run", "ch9/sees", "--profile", "smoke"]) == 0
    assert perturbation.relative() == 0.0
    twin = store.read_dataset(tmp_path / "results" / "smoke-perturbed" / "ch9" / "sees.nc")
    assert twin["seen"].values.tolist() == [1e-7]
    assert twin.attrs["perturbation_relative"] == 1e-7
    assert not (tmp_path / "results" / "smoke").exists()
    assert cli.main(["run", "ch9/sees", "--profile", "smoke"]) == 0
    plain = store.read_dataset(tmp_path / "results" / "smoke" / "ch9" / "sees.nc")
    assert plain["seen"].values.tolist() == [0.0]
    assert "perturbation_relative" not in plain.attrs
    with pytest.raises(SystemExit):
        cli.main(["--perturb", "0.5", "run", "ch9/sees", "--profile", "smoke"])
    assert "allowed values: 0 (off) to 1e-3" in capsys.readouterr().err


def test_perturbed_twin_reaches_the_model_checks(fake_registry, tmp_path, monkeypatch):
    """``thesis --perturb REL validate``: the model checks run under the perturbation too
    (the pipeline's perturbed twin of results/<profile>/model/ is a twin, not a rerun of
    the same bits), into results/<profile>-perturbed/model/."""
    monkeypatch.setitem(registry.EXPERIMENTS, "model/sees", "fake_experiments:sees_perturbation")
    monkeypatch.setitem(registry.VALIDATIONS, "fake", ("model/sees",))
    monkeypatch.chdir(tmp_path)
    assert cli.main(["--perturb", "1e-7", "validate", "fake", "--profile", "smoke"]) == 0
    twin = store.read_dataset(tmp_path / "results" / "smoke-perturbed" / "model" / "sees.nc")
    assert twin["seen"].values.tolist() == [1e-7]
    assert twin.attrs["perturbation_relative"] == 1e-7
    assert cli.main(["validate", "fake", "--profile", "smoke"]) == 0
    plain = store.read_dataset(tmp_path / "results" / "smoke" / "model" / "sees.nc")
    assert plain["seen"].values.tolist() == [0.0]


def test_config_slice_holds_what_the_experiment_reads():
    from thesis.config import load_config

    cfg = load_config("smoke")
    ball = cli.config_slice(cfg, "ch7/ball")
    assert set(ball) == {"root_seed", "jax", "ch7"}
    assert ball["ch7"] == {"ball": cfg["ch7"]["ball"]}
    assert cli.config_slice(cfg, "ch7/table7_1")["physics"] == {"bench": cfg["physics"]["bench"]}
    assert cli.config_slice(cfg, "ch3/fig3_4")["ch3"] == cfg["ch3"]
    assert cli.config_slice(cfg, "ch3") == cli.config_slice(cfg, "ch3/fig3_4")
    # another experiment's key does not reach this slice; its own does
    other = load_config("smoke", overrides={"ch7": {"arm_fixed": {"evaluations": 7}},
                                            "physics": {"bench": {"repeats": 2}}})
    assert cli.config_slice(other, "ch7/ball") == ball
    assert cli.config_slice(other, "ch7/arm_fixed") != cli.config_slice(cfg, "ch7/arm_fixed")
    assert cli.config_slice(other, "ch7/table7_1") != cli.config_slice(cfg, "ch7/table7_1")


def test_experiment_sees_only_the_config_it_declares(fake_registry, tmp_path, monkeypatch):
    out = tmp_path / "w.nc"
    monkeypatch.setitem(registry.READS, "ch2/widths", ("ch2.seeds",))
    with pytest.raises(KeyError, match="ffn_spn"):  # read but not declared
        cli.run_experiment("ch2/widths", "smoke", output=out)
    assert not out.exists()
    monkeypatch.setitem(registry.READS, "ch2/widths", ("ch2.seeds", "ch2.ffn_spn"))
    cli.run_experiment("ch2/widths", "smoke", output=out, overrides={
        "ch2": {"ffn_spn": {"cls_dense": 7}}})
    ds = store.read_dataset(out)
    assert ds["width"].values.tolist() == [7.0]
    assert '"rnn_spn"' not in ds.attrs["config_json"]


def test_ch2_experiments_declare_narrow_slices():
    from thesis.config import load_config

    cfg = load_config("smoke")
    data = cli.config_slice(cfg, "ch2/cluttered_mnist")["ch2"]
    assert data == {"data": cfg["ch2"]["data"]}
    ffn = cli.config_slice(cfg, "ch2/table2_2_ffn_spn")["ch2"]
    assert "ffn_spn" in ffn and "rnn_spn" not in ffn and "data" not in ffn
    # an RNN-SPN setting reruns neither the data nor the FFN-SPN half
    other = load_config("smoke", overrides={"ch2": {"rnn_spn": {"step_shift": 0.1}}})
    for key in ("ch2/cluttered_mnist", "ch2/table2_2_ffn_spn", "ch2/chirpz_scaling"):
        assert cli.config_slice(other, key) == cli.config_slice(cfg, key)
    for key in ("ch2/table2_2_rnn_spn", "ch2/table2_2"):
        assert cli.config_slice(other, key) != cli.config_slice(cfg, key)


def test_sigterm_during_an_atomic_write_leaves_nothing(tmp_path):
    """A job killed by its scheduler (SIGTERM) removes its temporary file on the way out."""
    import signal
    import subprocess
    import sys

    script = (
        "import signal, sys, time\n"
        "from thesis import cli, store\n"
        "signal.signal(signal.SIGTERM, cli._terminate)\n"
        f"with store.atomic_path({str(tmp_path / 'out.nc')!r}) as tmp:\n"
        "    tmp.write_text('half')\n"
        "    print('ready', flush=True)\n"
        "    time.sleep(60)\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline().strip() == "ready"
    assert len(list(tmp_path.iterdir())) == 1  # the temporary file exists while it works
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=30) == 128 + signal.SIGTERM
    assert list(tmp_path.iterdir()) == []


def test_config_json_reaches_the_job_under_each_set(fake_registry, tmp_path, capsys):
    """``thesis --config-json`` (how the pipeline passes ``snakemake --config`` on) is merged
    over the profile and each ``--set`` over it; a value the schema refuses is an error
    naming its key, and something that is not a JSON object is refused."""
    out = tmp_path / "j.nc"
    assert cli.main(["--config-json", '{"root_seed": 5, "ch2": {"seeds": [0]}}', "run",
                     "ch9/good", "--profile", "smoke", "--output", str(out)]) == 0
    assert store.read_dataset(out)["distance"].values.tolist() == [5.0, 10.0]
    out2 = tmp_path / "k.nc"
    assert cli.main(["--config-json", '{"root_seed": 5}', "run", "ch9/good", "--profile",
                     "smoke", "--output", str(out2), "--set", "root_seed=2"]) == 0
    assert store.read_dataset(out2)["distance"].values.tolist() == [2.0, 4.0]
    assert cli.main(["--config-json", '{"root_seed": -1}', "run", "ch9/good", "--profile",
                     "smoke", "--output", str(tmp_path / "bad.nc")]) == 2
    assert "root_seed" in capsys.readouterr().err
    with pytest.raises(SystemExit, match="JSON object"):
        cli.main(["--config-json", "[1]", "run", "ch9/good", "--profile", "smoke"])
