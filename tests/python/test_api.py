"""The package's namespace is its API: ``dir(dualspectra)`` lists what ``__all__`` names (and
private ``_`` names), no helper module or typing name leaks (``np``, ``os``, ``Optional``)."""

import pickle

import dualspectra as ds


def test_dir_lists_only_the_api() -> None:
    public = {name for name in dir(ds) if not name.startswith("_")}
    assert public == {name for name in ds.__all__ if not name.startswith("_")}, public ^ set(ds.__all__)
    assert len(set(ds.__all__)) == len(ds.__all__), "a name listed twice"


def test_every_name_in_all_resolves() -> None:
    for name in ds.__all__:
        assert getattr(ds, name) is not None, name
    # The classes and functions defined in Python read as the package's.
    for name in ("Localizer", "DualspectraWarning", "localize", "search", "read_mesh"):
        assert getattr(ds, name).__module__ == "dualspectra", name


def test_search_batch_ranks_by_the_cores_rule() -> None:
    # The rule the batch calls (the core's search::rank): lowest score first, ties by index,
    # inf last, the top kept.
    from dualspectra import _dualspectra

    scored = [(0.3, 4), (float("inf"), 0), (0.1, 2), (0.3, 1), (0.2, 3)]
    assert _dualspectra.rank(scored) == [2, 4, 3, 0, 1]
    assert _dualspectra.rank(scored, 2) == [2, 4]
    assert _dualspectra.rank([], None) == []


def test_old_pickles_find_the_unpickler() -> None:
    # Pickles made before 0.3.0 name dualspectra._unpickle_localizer (a protocol-0 GLOBAL).
    assert pickle.loads(b"cdualspectra\n_unpickle_localizer\n.") is ds._api._unpickle_localizer
