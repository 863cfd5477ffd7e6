"""Departures from the thesis are declared data: every config value that differs from the
thesis's stated setup (a ``thesis.paper`` setup entry) is declared, with the results it
reaches; every declaration names real config paths, paper keys and results."""

from __future__ import annotations

import pytest

from thesis import departures, paper, registry
from thesis.config import PROFILES, load_config
from thesis.departures import DEPARTURES, Departure


def _readers(path: str) -> set[str]:
    """Registered experiments whose declared config slice contains ``path``."""
    return {k for k in registry.EXPERIMENTS
            if any(path == r or path.startswith(r + ".") for r in registry.reads(k))}


def undeclared(profile: str, config: dict, decls=DEPARTURES) -> list[str]:
    """Setup values of ``config`` that differ from the thesis without a covering deviation."""
    problems = []
    for e in paper.setup():
        value = departures.config_value(config, e.config)
        if e.matches_config(value):
            continue
        cover = [d for d in decls if d.kind == "deviation" and e.config in d.config
                 and e.key in d.paper_keys]
        if not cover:
            problems.append(f"{profile}: {e.config} = {value!r} differs from the thesis's "
                            f"{e.value:g} ({e.key}) and no deviation declares it")
            continue
        missing = _readers(e.config) - set().union(*(set(d.results) for d in cover))
        if missing:
            problems.append(f"{profile}: {e.config} differs from the thesis; "
                            f"{sorted(missing)} read it but no deviation names them")
    return problems


@pytest.mark.parametrize("profile", PROFILES)
def test_every_difference_from_the_stated_setup_is_declared(profile):
    assert undeclared(profile, load_config(profile)) == []


def test_an_undeclared_difference_fails():
    cfg = load_config("default")
    assert cfg["ch7"]["gait"]["servo_torque"] == paper.get(
        "quadruped_gait/servo_torque").value  # the default profile uses the thesis's
    cfg["ch7"]["gait"]["servo_torque"] = 40.0
    without = tuple(d for d in DEPARTURES if d.id != "ch7.gait_scale")
    problems = undeclared("default", cfg, without)
    assert len(problems) == 1 and "ch7.gait.servo_torque" in problems[0]
    assert undeclared("default", cfg) == []  # the declaration covers it


def test_a_deviation_must_name_every_result_that_reads_the_value():
    cfg = load_config("default")
    narrow = tuple(Departure(**{**d.__dict__, "results": ("ch2/table2_2",)})
                   if d.id == "ch2.network_widths" else d for d in DEPARTURES)
    problems = undeclared("default", cfg, narrow)
    assert problems and all("ch2/table2_2_ffn_spn" in p or "ch2/table2_2_rnn_spn" in p
                            for p in problems)


def test_declarations_name_real_paths_keys_and_results():
    known = set(registry.EXPERIMENTS)
    for profile in PROFILES:
        cfg = load_config(profile)
        for d in DEPARTURES:
            for path in d.config:
                departures.config_value(cfg, path)  # KeyError names the bad path
    for d in DEPARTURES:
        assert set(d.results) <= known, d.id
        for k in d.paper_keys:
            e = paper.get(k)  # a setup entry's path must be named; a result is a reference
            assert not e.config or e.config in d.config, (d.id, k, "config path not named")
        # a choice may cite the thesis numbers it is derived from (e.g. ch4's generations
        # from "6 km in 4 hours"); only a deviation's setup entries decide "in effect"
        assert d.thesis and d.ours and d.why, d.id


def test_departure_texts_write_no_thesis_number():
    """A thesis number is referred to by its paper key, never typed into the text (small
    integers such as a d = 2 of our own are too common to tell apart and are not checked)."""
    for d in DEPARTURES:
        for k in d.paper_keys:
            v = paper.get(k).value
            if v is None or (float(v).is_integer() and abs(v) <= 10):
                continue
            for text in (d.thesis, d.ours, d.why):
                assert not any(abs(n - v) < 1e-9 for n in paper.numbers_in(text)), (d.id, k)


def test_records_carry_the_run_config_values():
    cfg = load_config("default")
    recs = {r["id"]: r for r in departures.records("ch7/arm_fixed", cfg)}
    assert recs["ch7.arm_servo_torque"]["config"] == {
        "ch7.arm_fixed.servo_torque": cfg["ch7"]["arm_fixed"]["servo_torque"],
        "ch7.arm_random.servo_torque": cfg["ch7"]["arm_random"]["servo_torque"]}
    assert recs["ch7.arm_servo_torque"]["kind"] == "deviation"
    assert "ch7.pendulum_speed_weight" not in recs
    with pytest.raises(KeyError, match="ch7.no_such"):
        departures.config_value(cfg, "ch7.no_such.key")


def test_bad_declarations_are_refused():
    with pytest.raises(ValueError, match="kind"):
        Departure(id="ch7.x", kind="guess", results=("ch7/ball",), thesis="t", ours="o",
                  why="w")
    with pytest.raises(ValueError, match="names no result"):
        Departure(id="ch7.x", kind="choice", results=(), thesis="t", ours="o", why="w")
    with pytest.raises(ValueError, match="thesis_config"):
        Departure(id="ch7.x", kind="deviation", results=("ch7/ball",), thesis="t", ours="o",
                  why="w", config=("ch7.ball.dt",), thesis_config=(("ch7.ball.seeds", 1),))
