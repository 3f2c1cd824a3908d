"""A run folder as a whole: nothing but folders and regular files below it, at most 32 deep
(hard links only where a run writes in place), the files of one folder checked, its own path
no link."""

import os

import pytest

from animat.learners.storage.files import UnsafeFile
from animat.learners.storage.tree import MAX_TREE_DEPTH, check_tree, listing, run_folder


def test_check_tree_names_the_first_entry_that_is_not_a_plain_file_or_folder(folder, outside):
    check_tree(folder)
    (folder / "tb").mkdir()
    os.mkfifo(folder / "tb" / "events")
    with pytest.raises(UnsafeFile, match="events: is a FIFO"):
        check_tree(folder)
    (folder / "tb" / "events").unlink()
    os.link(outside, folder / "tb" / "events")
    check_tree(folder)  # read, a hard-linked copy (cp -al, rsync --link-dest) is a plain file
    with pytest.raises(UnsafeFile, match="events: has 1 other hard link"):
        check_tree(folder, writing=True)  # a run appends in place
    (folder / "tb" / "events").unlink()
    deep = folder.joinpath(*["d"] * MAX_TREE_DEPTH)
    deep.mkdir(parents=True)
    with pytest.raises(UnsafeFile, match="nested more than 32 folders deep"):
        check_tree(folder)


def test_listing_checks_each_file_and_its_folder(folder, outside):
    assert listing(folder / "tb", "events.*", "events") == []
    (folder / "tb").mkdir()
    (folder / "tb" / "events.1").write_bytes(b"x")
    assert listing(folder / "tb", "events.*", "events") == [folder / "tb" / "events.1"]
    (folder / "tb" / "events.2").symlink_to(outside)
    with pytest.raises(UnsafeFile, match="events.2: is a symbolic link"):
        listing(folder / "tb", "events.*", "events")


def test_run_folder_resolves_its_parents_and_refuses_its_own_link(folder):
    (folder.parent / "runs").symlink_to(folder.parent)
    assert run_folder(folder.parent / "runs" / "run") == folder
    (folder.parent / "alias").symlink_to(folder)
    with pytest.raises(UnsafeFile, match="alias: is a symbolic link"):
        run_folder(folder.parent / "alias")
