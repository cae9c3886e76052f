"""Splitting points over ranks (issue 4): every (n, size), including size > n."""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.parallel.partition import block_range, cyclic_indices, owner_of_rows, split


@pytest.mark.parametrize("how", ["block", "cyclic", "scattered"])
def test_every_split_covers_without_overlap_and_balances(how):
    for n in range(1, 41):
        for size in range(1, 51):
            parts = [split(n, size, rank, how) for rank in range(size)]
            joined = np.concatenate(parts)
            assert np.array_equal(np.sort(joined), np.arange(n)), (n, size)
            counts = [len(p) for p in parts]
            assert max(counts) - min(counts) <= 1, (n, size, counts)


def test_block_range_is_contiguous_and_ordered():
    for n in range(0, 41):
        for size in range(1, 51):
            expected_start = 0
            for rank in range(size):
                start, count = block_range(n, size, rank)
                assert start == expected_start and count >= 0
                expected_start += count
            assert expected_start == n


def test_cyclic_deals_round_robin():
    assert cyclic_indices(7, 3, 1).tolist() == [1, 4]
    assert cyclic_indices(2, 5, 4).tolist() == []


def test_owner_of_rows_matches_block_range():
    for ny in range(1, 20):
        for size in range(1, 25):
            owners = owner_of_rows(ny, size)
            for rank in range(size):
                start, count = block_range(ny, size, rank)
                assert (owners[start:start + count] == rank).all()


@pytest.mark.parametrize("bad", [(5, 0, 0), (5, 2, 2), (-1, 2, 0)])
def test_bad_arguments_raise(bad):
    with pytest.raises(ValueError):
        block_range(*bad)
    with pytest.raises(ValueError):
        cyclic_indices(*bad)
    with pytest.raises(ValueError, match="unknown split"):
        split(5, 2, 0, "dynamic")
