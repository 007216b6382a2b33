"""An experiment store (a SQLite file or a ``postgres://`` URL) as a pandas table: one row
per evaluation, the columns of ``proleg results --export``."""

from __future__ import annotations

from typing import Iterable

from . import _native


def read_store(location: str, runs: Iterable[int] | None = None):
    """Every evaluation of ``runs`` (all by default) in the store at ``location`` as a
    ``pandas.DataFrame``: ``store``, ``run``, ``evaluation``, ``round``, ``score``,
    ``best`` (the run's best score so far), ``wall_s``, ``genome`` and ``values`` (lists), ``engine_scores``, ``rejected`` and
    ``measures`` (a list). Needs pandas (``pip install proleg[pandas]``)."""
    try:
        import pandas as pd
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("read_store needs pandas: pip install pandas") from e
    columns = _native.read_store(str(location), None if runs is None else list(runs))
    return pd.DataFrame(columns)
