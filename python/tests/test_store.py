"""An experiment store read into pandas is the table `proleg results --export` writes, from
a SQLite file and from PostgreSQL (the private server `scripts/test` starts; its URL and
password come in PROLEG_TEST_PG_URL and PROLEG_TEST_PG_PASSWORD, the password reaching
proleg only through PGPASSWORD)."""

import os
import subprocess
import urllib.parse

import numpy as np
import pandas as pd
import pytest

import proleg


def _optimize_and_compare(store, tmp_path, proleg_bin, env=None):
    """Runs a short optimization into ``store`` and checks ``read_store`` against
    ``proleg results --export``."""
    config = proleg.scenario_path("gait_from_scratch_cmaes.simulation.xml")
    subprocess.run(
        [proleg_bin, "optimize", config, "--max-evals", "8", "--store", store,
         "-o", str(tmp_path / "best.actuation.xml")],
        check=True, capture_output=True, env=env,
    )
    tsv = tmp_path / "evals.tsv"
    subprocess.run([proleg_bin, "results", store, "--export", str(tsv)], check=True,
                   capture_output=True, env=env)
    exported = pd.read_csv(tsv, sep="\t", keep_default_na=False)
    df = proleg.read_store(store)
    assert list(df.columns) == list(exported.columns)
    assert len(df) == len(exported) >= 8
    for col in ["run", "evaluation", "round"]:
        assert (df[col].to_numpy() == exported[col].to_numpy()).all(), col
    assert np.array_equal(df["score"].to_numpy(), exported["score"].to_numpy())
    assert np.array_equal(df["best"].to_numpy(), exported["best"].to_numpy())
    finite = np.where(np.isfinite(df["score"]), df["score"], -np.inf)
    assert np.array_equal(df["best"].to_numpy(), np.maximum.accumulate(finite)), "best so far"

    assert (df["store"] == exported["store"]).all()
    assert [list(map(float, s.split())) for s in exported["values"]] == list(df["values"])
    assert [list(map(int, str(s).split())) for s in exported["genome"]] == list(df["genome"])


def test_a_store_read_into_pandas_equals_the_exported_table(tmp_path, proleg_bin):
    _optimize_and_compare(str(tmp_path / "gait.results.sqlite"), tmp_path, proleg_bin)


def _pg_server():
    """The test server's admin URL (no password) and password."""
    url, password = os.environ.get("PROLEG_TEST_PG_URL"), os.environ.get("PROLEG_TEST_PG_PASSWORD")
    if not url or not password:
        pytest.fail("no test PostgreSQL server: run scripts/test (it starts one), or "
                    '`eval "$(scripts/pg-test-server start /tmp/pgtest)"` before pytest')
    return url, password


def _pg_database(name):
    """A new, empty database on the test server: its URL (no password) and an environment
    with the password in PGPASSWORD."""
    url, password = _pg_server()
    u = urllib.parse.urlparse(url)
    env = dict(os.environ, PGPASSWORD=password)
    env.pop("PGPASSFILE", None)
    where = ["-h", u.hostname, "-p", str(u.port), "-U", u.username]
    subprocess.run(["dropdb", *where, "--if-exists", "--force", name], check=True, env=env,
                   capture_output=True)
    subprocess.run(["createdb", *where, name], check=True, env=env, capture_output=True)
    return u._replace(path="/" + name).geturl(), env


def test_a_postgres_store_read_into_pandas_equals_the_exported_table(
        tmp_path, proleg_bin, monkeypatch):
    url, env = _pg_database("pytest_read_store")
    monkeypatch.setenv("PGPASSWORD", env["PGPASSWORD"])
    _optimize_and_compare(url, tmp_path, proleg_bin, env)


def test_a_wrong_postgres_password_raises_without_showing_it(monkeypatch):
    url, env = _pg_database("pytest_wrong_password")
    wrong = "not-the-" + env["PGPASSWORD"][:4] + "-password"
    monkeypatch.setenv("PGPASSWORD", wrong)
    with pytest.raises(proleg.ProlegError) as e:
        proleg.read_store(url)
    assert "password" in str(e.value).lower()
    assert wrong not in str(e.value) and env["PGPASSWORD"] not in str(e.value)


def test_a_missing_store_raises_naming_it(tmp_path):
    with pytest.raises(proleg.ProlegError, match="nothing.sqlite"):
        proleg.read_store(str(tmp_path / "nothing.sqlite"))
