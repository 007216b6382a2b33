"""An experiment store read into pandas is the table `proleg results --export` writes."""

import subprocess

import numpy as np
import pandas as pd
import pytest

import proleg


def test_a_store_read_into_pandas_equals_the_exported_table(tmp_path, proleg_bin):
    store = tmp_path / "gait.results.sqlite"
    config = proleg.scenario_path("gait_from_scratch_cmaes.simulation.xml")
    subprocess.run(
        [proleg_bin, "optimize", config, "--max-evals", "8", "--store", str(store),
         "-o", str(tmp_path / "best.actuation.xml")],
        check=True, capture_output=True,
    )
    tsv = tmp_path / "evals.tsv"
    subprocess.run([proleg_bin, "results", str(store), "--export", str(tsv)], check=True,
                   capture_output=True)
    exported = pd.read_csv(tsv, sep="\t", keep_default_na=False)
    df = proleg.read_store(str(store))
    assert list(df.columns) == list(exported.columns)
    assert len(df) == len(exported) >= 8
    for col in ["run", "evaluation", "round"]:
        assert (df[col].to_numpy() == exported[col].to_numpy()).all(), col
    assert np.array_equal(df["score"].to_numpy(), exported["score"].to_numpy())
    assert (df["store"] == exported["store"]).all()
    joined = df["values"].map(lambda v: " ".join(repr(x) for x in v))
    assert [list(map(float, s.split())) for s in exported["values"]] == list(df["values"])
    assert [list(map(int, str(s).split())) for s in exported["genome"]] == list(df["genome"])
    assert len(joined) == len(df)


def test_a_missing_store_raises_naming_it(tmp_path):
    with pytest.raises(proleg.ProlegError, match="nothing.sqlite"):
        proleg.read_store(str(tmp_path / "nothing.sqlite"))
