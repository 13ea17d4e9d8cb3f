"""The work queue of a refinement run: triangles by (key, triangle), smallest first."""

from __future__ import annotations

import heapq
from collections.abc import Hashable
from typing import Any

from geomexact.mesh2d.snapshot import Triangle


def rank(key: Any) -> float:
    """A float that orders like ``key`` where it can (monotone: never inverts two keys),
    so most comparisons in the queue are float comparisons."""
    try:
        return float(key)
    except OverflowError:
        return float("inf") if key > 0 else float("-inf")
    except (TypeError, ValueError):
        return 0.0


class WorkQueue:
    """Triangles by priority: ``pop`` returns the triangle with the smallest (key,
    triangle), as one heap of such pairs would, but stores each distinct key once (a heap
    of (rank, key)) with a heap of its triangles, so that equal keys — common, e.g. equal
    areas — cost integer comparisons only.  Keys must be hashable and totally ordered."""

    __slots__ = ("buckets", "keys", "size")

    def __init__(self) -> None:
        self.buckets: dict[Hashable, list[Triangle]] = {}
        self.keys: list[tuple[float, Any]] = []
        self.size = 0

    def push(self, key: Any, triangle: Triangle) -> None:
        bucket = self.buckets.get(key)
        if bucket is None:
            self.buckets[key] = [triangle]
            heapq.heappush(self.keys, (rank(key), key))
        else:
            heapq.heappush(bucket, triangle)
        self.size += 1

    def pop(self) -> Triangle | None:
        keys = self.keys
        if not keys:
            return None
        key = keys[0][1]
        bucket = self.buckets[key]
        triangle = heapq.heappop(bucket)
        if not bucket:
            heapq.heappop(keys)
            del self.buckets[key]
        self.size -= 1
        return triangle

