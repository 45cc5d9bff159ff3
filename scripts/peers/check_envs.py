"""Checks that a peers' Python environment is the one of its competition year (dev-time).

    venv-2021/bin/python scripts/peers/check_envs.py 2021
    venv/bin/python scripts/peers/check_envs.py 2022

Each tool of the field runs with the libraries of its own competition (setup.sh), since a library
that changed under a tool makes it crash where it did not crash then, and the run measures the
harness rather than the tool. This checks the pinned versions and, for 2021, the one call known
to have changed: Frenetic (2021) marks the parent it mutates with
`df.at[parent.index, 'visited'] = True`, where `parent` is a one-row frame (`head(1)`), so the row
key is an Index, not a label. pandas 1.2 set that row: the scalar setter's lookup of an
unhashable key failed with a TypeError, and its fallback was `df.loc[key, column] = value`
(`DataFrame._set_value`). pandas 1.3 still sets it (the 2022 tools' pin); pandas 1.4 raises
`InvalidIndexError`, and pandas 1.5 the same with "You can only assign a scalar value not a
<class 'bool'>", which ended every Frenetic (2021) run on beamng-ai-proxy at its mutation phase,
half-way through its budget. (FreneticV and AdaFrenetic have the same line;
their random phase is the whole generation budget, so they do not reach it under the
competition's budgets, and a run that did would end in a crash the campaign names as the
harness's.)

Exit status 0 when the environment is as it should be, 1 with what differs otherwise.
"""
import sys

PINS = {
    "2021": {"numpy": "1.19.3", "scipy": "1.5.4", "pandas": "1.2.2", "shapely": "1.8.5.post1"},
    "2022": {"numpy": "1.23.5", "scipy": "1.9.3", "pandas": "1.5.3", "shapely": "1.8.5.post1",
             "pymoo": "0.4.2.2"},
}


def at_with_a_one_row_index_sets_the_row():
    """What Frenetic (2021)'s mutation phase does first: True when the row is marked as in 2021."""
    import pandas as pd
    df = pd.DataFrame({"visited": [False, False, False], "min_oob_distance": [3.0, -1.0, 2.0]})
    parent = df[~df.visited].sort_values("min_oob_distance").head(1)
    try:
        df.at[parent.index, "visited"] = True
    except Exception as e:  # the 2022 pandas' InvalidIndexError
        print(f"  df.at[one-row Index, column] = True raises {type(e).__name__}: {e}")
        return False
    return df.visited.tolist() == [False, True, False] and df.visited.dtype == bool


def main():
    if len(sys.argv) != 2 or sys.argv[1] not in PINS:
        sys.exit(f"usage: check_envs.py {'|'.join(PINS)}")
    year = sys.argv[1]
    problems = []
    for module, pinned in PINS[year].items():
        try:
            found = __import__(module).__version__
        except ImportError:
            found = "missing"
        if found != pinned:
            problems.append(f"{module} {found}, not {pinned}")
    if year == "2021" and not at_with_a_one_row_index_sets_the_row():
        problems.append("pandas does not set the row Frenetic (2021) marks as visited")
    if problems:
        print(f"check_envs.py: {sys.executable} is not the {year} environment: " + "; ".join(problems))
        sys.exit(1)
    print(f"check_envs.py: {sys.executable}: the {year} environment")


if __name__ == "__main__":
    main()
