"""The broad phase of the hand-point queries: an object's pieces stacked once, and cheap bounds of cP.

`PieceIndex` is built once per object (`GraspObject.index`). It owns the
pieces' facet planes, vertices and the quantities derived from them (the
facets' reach along the simplex directions, the support function, the
vertex clusters of the nearest-vertex search), the warm-start bases of the
cP LP blocks (`synergrasp.lp.blocks.BasisMemory`), and the bounds of cP that
need no LP:

* for the regular simplex Q, ``|x| <= gauge_Q(x) <= 3 |x|``, so if e_j is
  the Euclidean distance from p to piece j, the piece's value lies in
  ``[e_j, 3 e_j]`` (python-fcl's GJK gives e_j);
* the gauge itself: the value of piece j is at least
  ``3 max_k (q_k . p - h_j(q_k))`` (h_j the support function), at least
  ``(n_f . p + o_f) / -min_k n_f . q_k`` for each facet plane f (the gauge
  ball ``p + t Q`` reaches the half-space behind the plane only from that
  t on), and at most the gauge distance to any of its vertices;
* the facet planes give an exact inside test: a point inside some piece
  only needs the pieces containing it (the others have values >= 0).

Every bound is valid, so pruning with them never changes a value.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import fcl
import numpy as np

from .._jit import helper, kernel
from ..lp.blocks import BasisMemory
from ..pseudo_distance import regular_simplex
from ..tolerances import VALUE_TOL

#: The default simplex Q of the hand-point queries (regular, circumradius 1, in 3-D).
SIMPLEX = regular_simplex(3)
SIMPLEX.setflags(write=False)
#: Lipschitz ratio of the regular-simplex gauge to the Euclidean norm in 3-D.
GAUGE_RATIO = 3.0
#: Vertices per cluster in the nearest-vertex search (`PieceIndex.probe`).
VERTEX_CLUSTER = 16


@dataclass(frozen=True)
class Probe:
    """What the broad phase knows of hand points before any LP.

    Only the pieces whose gauge support bound is within the round-off
    tolerance of ``upper`` can be a point's cP minimiser or contain it (the
    bound is then <= 0); the facet planes of the other pieces are not
    evaluated for that point.

    Attributes
    ----------
    P : (n, 3) float
        The points.
    PQ : (n, 4) float
        ``q_k . p``.
    S : (n, J) float
        ``max_f n_f . p + o_f`` over the facets of each piece evaluated: <= 0
        inside piece j, else a lower bound of the Euclidean distance; inf for
        the pieces not evaluated.
    lower : (n, J) float
        Lower bound of piece j's value (the support and facet-plane gauge
        bounds); inf for the pieces not evaluated.
    upper : (n,) float
        Gauge distance to the nearest vertex, an upper bound of cP.
    """

    P: np.ndarray
    PQ: np.ndarray
    S: np.ndarray
    lower: np.ndarray
    upper: np.ndarray

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds of each point's cP: ``(min_j lower, upper)`` outside, ``(-inf, 0)`` inside a piece.

        Returns
        -------
        lower, upper : (n,) float
        """
        inside = (self.S <= 0.0).any(axis=1)
        return np.where(inside, -np.inf, self.lower.min(axis=1)), np.where(inside, 0.0, self.upper)


def loosened(upper):
    """An upper bound of cP plus the round-off tolerance of the pruning."""
    return upper + VALUE_TOL * (1.0 + np.abs(upper))


class PieceIndex:
    """An object's convex pieces stacked for the hand-point queries (built once per object).

    Parameters
    ----------
    pieces : sequence of ConvexPiece

    Attributes
    ----------
    pieces : tuple of ConvexPiece
    planes : (F, 4) float
        The facet planes ``[n, o]`` of all pieces, piece by piece (F facets in all).
    plane_start : (J+1,) int64
        Piece j's planes are rows ``plane_start[j] ... plane_start[j+1] - 1``.
    facet_counts : (J,) int64
        Facets of each piece.
    vertices : (V, 3) float
        The vertices of all pieces, piece by piece.
    facet_vertices : (F, 3) int64
        Each facet's vertices as rows of ``vertices``.
    edges : (E, 2) int64
        The facets' edges, each once, as pairs of rows of ``vertices``.
    facet_q : (F, 4) float
        ``n_f . q_k`` for each facet's outward normal and simplex vertex.
    facet_nq : (F,) float
        ``min_k n_f . q_k`` (< 0: the simplex's vertices span every direction).
    facet_reach : (F,) float
        ``1 / -facet_nq``.
    facet_mq : (4, F) float
        ``min over the facet's vertices t of -q_k . t``.
    support : (J, 4) float
        Support function ``max_v q_k . v`` of each piece along the simplex vertices.
    boxes : (J, 2, 3) float
        Each piece's axis-aligned bounding box: its lower, then its upper corner.
    memory : synergrasp.lp.blocks.BasisMemory
        The last optimal bases of the cP LP blocks of this object (warm starts).

    Examples
    --------
    >>> from synergrasp import objects
    >>> index = objects.ellipsoid().index
    >>> index.n_pieces, index.planes.shape
    (1, (1280, 4))
    >>> index.plane_bounds([[0.0, 0.0, 60.0], [0.0, 0.0, 0.0]]).round(1).tolist()   # > 0 outside, < 0 inside
    [[9.9], [-29.9]]
    """

    def __init__(self, pieces):
        self.pieces = tuple(pieces)
        self.planes = np.ascontiguousarray(np.vstack([p.planes for p in self.pieces]))
        self.facet_counts = np.array([len(p.planes) for p in self.pieces], dtype=np.int64)
        self.plane_start = np.concatenate([[0], np.cumsum(self.facet_counts)]).astype(np.int64)
        self.vertices = np.ascontiguousarray(np.vstack([p.vertices for p in self.pieces]))
        offsets = np.cumsum([0] + [len(p.vertices) for p in self.pieces[:-1]])
        self.facet_vertices = np.ascontiguousarray(np.vstack([p.facets + o for p, o in zip(self.pieces, offsets)]),
                                                   dtype=np.int64)
        pairs = self.facet_vertices[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
        self.edges = np.ascontiguousarray(np.unique(np.sort(pairs, axis=1), axis=0))
        self.facet_q = np.ascontiguousarray(self.planes[:, :3] @ SIMPLEX.T)
        self.facet_nq = self.facet_q.min(axis=1)
        self.facet_reach = 1.0 / -self.facet_nq
        self.facet_mq = np.ascontiguousarray(
            np.vstack([(-(p.vertices @ SIMPLEX.T))[p.facets].min(axis=1) for p in self.pieces]).T)
        self.support = np.ascontiguousarray([(p.vertices @ SIMPLEX.T).max(axis=0) for p in self.pieces])
        self.boxes = np.array([[p.vertices.min(axis=0), p.vertices.max(axis=0)] for p in self.pieces])
        vq, first = np.unique(self.vertices @ SIMPLEX.T, axis=0, return_index=True)
        clusters = median_split(self.vertices[first], VERTEX_CLUSTER)
        members = vq[np.stack([np.resize(c, VERTEX_CLUSTER) for c in clusters])]  # (C, VERTEX_CLUSTER, 4)
        self._members = np.ascontiguousarray(members)
        self._cluster_support = np.ascontiguousarray(members.max(axis=1))  # (C, 4)
        self.memory = BasisMemory()
        for a in (self.planes, self.plane_start, self.facet_counts, self.vertices, self.facet_vertices, self.edges,
                  self.facet_q, self.facet_nq, self.facet_reach, self.facet_mq, self.support, self.boxes):
            a.setflags(write=False)

    def forget(self) -> None:
        """Drop the remembered bases of the cP LP blocks (the next ones start cold)."""
        self.memory = BasisMemory()

    @cached_property
    def fcl_manager(self) -> fcl.DynamicAABBTreeCollisionManager:
        """python-fcl's broad phase over the pieces (a dynamic AABB tree), for the capsule queries."""
        manager = fcl.DynamicAABBTreeCollisionManager()
        manager.registerObjects([p.fcl for p in self.pieces])
        manager.setup()
        return manager

    @property
    def n_pieces(self) -> int:
        """Number of pieces J."""
        return len(self.pieces)

    def plane_bounds(self, points) -> np.ndarray:
        """``max_f n_f . p + o_f`` over each piece's facets: <= 0 inside piece j, else a lower bound of the distance.

        Parameters
        ----------
        points : (n, 3) float

        Returns
        -------
        (n, J) float
        """
        P = np.ascontiguousarray(points, dtype=float)
        out = np.empty((len(P), self.n_pieces))
        _plane_bounds(P, self.planes, self.plane_start, out)
        return out

    def min_plane_bound(self, points) -> np.ndarray:
        """``min_j`` of `plane_bounds`: <= 0 inside the union of the pieces, else a lower bound of the distance to it.

        Equal to ``plane_bounds(points).min(axis=1)``, computed without the
        full table: a piece's facets are left as soon as their maximum exceeds
        the smallest bound found so far, and each point starts from the piece
        that was nearest to the point before it (which pays when nearby points
        come in turn).

        Parameters
        ----------
        points : (n, 3) float

        Returns
        -------
        (n,) float
            NaN for a point with a NaN or infinite coordinate.
        """
        P = np.ascontiguousarray(points, dtype=float)
        out = np.empty(len(P))
        _min_plane_bound(P, self.planes, self.plane_start, out)
        return out

    def inside(self, points) -> np.ndarray:
        """Whether each point is in the union of the pieces: ``min_plane_bound(points) <= 0``, without the bounds.

        A piece is left at its first facet plane with the point outside, and a
        point at the first piece that holds it: no maximum or minimum is
        needed, only its sign.

        Parameters
        ----------
        points : (n, 3) float

        Returns
        -------
        (n,) bool
            False for a point with a NaN or infinite coordinate.
        """
        P = np.ascontiguousarray(points, dtype=float)
        out = np.empty(len(P), dtype=np.bool_)
        _inside(P, self.planes, self.plane_start, out)
        return out

    def probe(self, points, planes: bool = True) -> Probe:
        """The broad phase's bounds for points (validated (n, 3) float).

        Parameters
        ----------
        points : (n, 3) float
        planes : bool
            Also evaluate the facet planes of the pieces within reach (the
            inside test and the plane gauge bound). False: only the support
            bound (``S`` is then inf, ``lower`` the support bound of every
            piece, valid inside a piece too).

        Returns
        -------
        Probe
        """
        P = np.ascontiguousarray(points, dtype=float)
        n = len(P)
        PQ, upper = np.empty((n, 4)), np.empty(n)
        S, lower = np.full((n, self.n_pieces), np.inf), np.full((n, self.n_pieces), np.inf)
        _probe(P, SIMPLEX, self._members, self._cluster_support, self.support, self.planes, self.plane_start,
               self.facet_reach, GAUGE_RATIO, VALUE_TOL, planes, np.empty(len(self._members)), PQ, upper, S, lower)
        return Probe(P, PQ, S, lower, upper)

    def group_probe(self, points, groups, far=None) -> tuple[np.ndarray, Probe, np.ndarray]:
        """The points that can attain their group's smallest cP, and their `Probe`.

        A point whose lower bound of cP exceeds the upper bound of another
        point of its group cannot attain the group's minimum (valid bounds, so
        the minima are unchanged). The support bound of every point comes
        first (no facet plane evaluated), then the facet-plane bounds of the
        points it leaves. With ``far``, a group whose points' bounds all
        exceed its ``far`` (beyond round-off; the support bounds, then the
        facet planes' of the points kept) is dropped whole: its cP is known to
        be larger, and ``floor`` bounds it.

        Parameters
        ----------
        points : (n, 3) float
        groups : (n,) int
            Group of each point, ``0 ... G-1``.
        far : (G,) float, optional
            The distance beyond which a group may be dropped (inf: never, the
            default for every group).

        Returns
        -------
        rows : (m,) int
            The points kept, ascending.
        probe : Probe
            Their probe (with the facet planes).
        floor : (G,) float
            A lower bound of each group's smallest cP (the smallest support
            bound of its points, or of a dropped group the facet planes' bound).
        """
        P = np.ascontiguousarray(points, dtype=float)
        groups = np.asarray(groups, dtype=np.int64)
        n, n_groups = len(P), int(groups.max()) + 1
        far = np.full(n_groups, np.inf) if far is None else np.array(far, dtype=float)  # writable: one compiled signature
        if far.shape != (n_groups,) or np.isnan(far).any():
            raise ValueError(f"far must be one distance per group ({n_groups}), not NaN, got shape {far.shape}")
        PQ, upper, keep = np.empty((n, 4)), np.empty(n), np.empty(n, dtype=bool)
        S, lower = np.full((n, self.n_pieces), np.inf), np.full((n, self.n_pieces), np.inf)
        floor = np.full(n_groups, np.inf)
        _group_probe(P, groups, SIMPLEX, self._members, self._cluster_support, self.support, self.planes,
                     self.plane_start, self.facet_reach, GAUGE_RATIO, VALUE_TOL, np.empty(len(self._members)), PQ,
                     upper, S, lower, np.full(n_groups, np.inf), np.empty(n), far, floor, np.full(n_groups, np.inf),
                     keep)
        rows = np.flatnonzero(keep)
        return rows, Probe(P[rows], PQ[rows], S[rows], lower[rows], upper[rows]), floor

    def candidates(self, probe: Probe) -> tuple[np.ndarray, np.ndarray]:
        """(n, J) bool: the pieces that can be each point's cP minimiser, and an upper bound of each cP.

        Inside some piece: the pieces containing the point. Outside, piece j
        is dropped when a lower bound of its value (``probe.lower``, and
        python-fcl's Euclidean distance e_j) exceeds an upper bound of
        another piece's value (``probe.upper``, and ``3 e_i``); fcl is only
        called for the points the cheap bounds leave with several candidates.

        Returns
        -------
        cand : (n, J) bool
        bound : (n,) float
            Upper bound of each point's cP (``probe.upper``, tightened by fcl).
        """
        S, lower = probe.S, probe.lower
        bound = probe.upper.copy()
        if S.shape[1] == 1:  # a single piece is every point's candidate: only the bound is needed
            return np.ones(S.shape, dtype=bool), bound
        inside = S <= 0.0
        cand = lower <= loosened(bound)[:, None]
        out = inside.any(axis=1)
        cand[out] = inside[out]
        todo = np.nonzero(~out & (cand.sum(axis=1) > 1))[0]
        if len(todo):
            query, request = fcl.CollisionObject(fcl.Sphere(0.0), fcl.Transform()), fcl.DistanceRequest()
        for i in todo.tolist():  # a few pieces per point: Python floats cost less than numpy's calls
            js = np.flatnonzero(cand[i]).tolist()
            query.setTranslation(probe.P[i])
            # fcl reports -1 for a point it finds on or in a piece
            exact = [max(fcl.distance(query, self.pieces[j].fcl, request, fcl.DistanceResult()), 0.0) for j in js]
            high = min(GAUGE_RATIO * min(exact), float(bound[i])) * (1 + 1e-6) + 1e-6
            row = lower[i].tolist()
            for j, e in zip(js, exact):
                cand[i, j] = max(e, row[j]) <= high
            bound[i] = min(float(bound[i]), high)
        return cand, bound


def median_split(points: np.ndarray, size: int) -> list[np.ndarray]:
    """Indices of ``points`` in clusters of at most ``size``, halving along the longest side.

    Parameters
    ----------
    points : (n, 3) float
    size : int

    Returns
    -------
    list of (m,) int
        The clusters (``size // 2 <= m <= size`` when ``n > size``).

    Examples
    --------
    >>> sorted(len(c) for c in median_split(np.random.default_rng(0).normal(size=(40, 3)), 16))
    [10, 10, 10, 10]
    """
    todo, done = [np.arange(len(points))], []
    while todo:
        idx = todo.pop()
        if len(idx) <= size:
            done.append(idx)
            continue
        coords = points[idx]
        order = idx[np.argsort(coords[:, np.argmax(np.ptp(coords, axis=0))], kind="stable")]
        todo += [order[: len(order) // 2], order[len(order) // 2 :]]
    return done


@kernel
def _plane_bounds(P, planes, plane_start, out):
    n, J = len(P), len(plane_start) - 1
    for i in range(n):
        x, y, z = P[i, 0], P[i, 1], P[i, 2]
        for j in range(J):
            sub = planes[plane_start[j]:plane_start[j + 1]]
            best = -np.inf
            for f in range(len(sub)):
                best = max(best, x * sub[f, 0] + y * sub[f, 1] + z * sub[f, 2] + sub[f, 3])
            out[i, j] = best


@kernel
def _min_plane_bound(P, planes, plane_start, out):
    J = len(plane_start) - 1
    first = 0
    for i in range(len(P)):
        x, y, z = P[i, 0], P[i, 1], P[i, 2]
        if not (np.isfinite(x) and np.isfinite(y) and np.isfinite(z)):
            out[i] = np.nan
            continue
        best, nearest = np.inf, first
        for step in range(J):
            j = (first + step) % J
            value = -np.inf
            for f in range(plane_start[j], plane_start[j + 1]):
                value = max(value, x * planes[f, 0] + y * planes[f, 1] + z * planes[f, 2] + planes[f, 3])
                if value >= best:
                    break
            if value < best:
                best = value
                nearest = j
        out[i] = best
        first = nearest


@kernel
def _inside(P, planes, plane_start, out):
    J = len(plane_start) - 1
    for i in range(len(P)):
        x, y, z = P[i, 0], P[i, 1], P[i, 2]
        out[i] = False
        if not (np.isfinite(x) and np.isfinite(y) and np.isfinite(z)):
            continue
        for j in range(J):
            sub = planes[plane_start[j]:plane_start[j + 1]]
            held = True
            for f in range(len(sub)):
                if x * sub[f, 0] + y * sub[f, 1] + z * sub[f, 2] + sub[f, 3] > 0.0:
                    held = False
                    break
            if held:
                out[i] = True
                break


@helper
def _probe_point(i, P, Q, members, cluster_support, support, planes, plane_start, reach, ratio, tol, with_planes, low,
                 PQ, upper, S, lower):
    """Row i of the `Probe` arrays (``S`` and ``lower`` inf on entry; ``low`` scratch).

    The nearest vertex in the gauge, ``min_v max_k (q_k . p - q_k . v)``:
    the cluster with the smallest bound ``max_k (q_k . p - max_v q_k . v)``
    first, then only the clusters whose bound can beat the best so far (the
    minimum over the same rounded differences: exact). Then, per piece, the
    support bound ``3 max_k (q_k . p - h_j(q_k))`` (valid inside the piece
    too) and, with ``with_planes``, for the pieces it leaves within reach,
    the facet planes' maximum and gauge bound.
    """
    J, C = len(support), len(members)
    x, y, z = P[i, 0], P[i, 1], P[i, 2]
    for k in range(4):
        PQ[i, k] = _pq(x, y, z, Q, k)
    pq0, pq1, pq2, pq3 = PQ[i, 0], PQ[i, 1], PQ[i, 2], PQ[i, 3]
    first = 0
    for c in range(C):
        low[c] = max(max(pq0 - cluster_support[c, 0], pq1 - cluster_support[c, 1]),
                     max(pq2 - cluster_support[c, 2], pq3 - cluster_support[c, 3]))
        if low[c] < low[first]:
            first = c
    best = np.inf
    for step in range(C + 1):
        c = first if step == 0 else step - 1
        if (step > 0 and c == first) or low[c] >= best:
            continue
        cluster = members[c]
        for m in range(len(cluster)):
            best = min(best, max(max(pq0 - cluster[m, 0], pq1 - cluster[m, 1]), max(pq2 - cluster[m, 2], pq3 - cluster[m, 3])))
    upper[i] = ratio * best
    reach_bound = upper[i] + tol * (1.0 + abs(upper[i]))
    for j in range(J):
        s = _support_bound(pq0, pq1, pq2, pq3, support, j, ratio)
        if not with_planes:
            lower[i, j] = s
            continue
        if J > 1 and max(s, 0.0) > reach_bound:  # it can be neither the minimiser nor contain the point
            continue
        f0, f1 = plane_start[j], plane_start[j + 1]
        sub, rf = planes[f0:f1], reach[f0:f1]  # loops from 0 over slices compile to much faster code
        smax, gmax = -np.inf, -np.inf
        for f in range(f1 - f0):
            v = x * sub[f, 0] + y * sub[f, 1] + z * sub[f, 2] + sub[f, 3]
            smax = max(smax, v)
            gmax = max(gmax, v * rf[f])
        S[i, j] = smax
        lower[i, j] = max(max(gmax, 0.0), s)


@kernel
def _probe(P, Q, members, cluster_support, support, planes, plane_start, reach, ratio, tol, with_planes, low,
           PQ, upper, S, lower):
    """The arrays of `Probe` (see `PieceIndex.probe`), into ``PQ``, ``upper``, ``S`` and ``lower`` (inf on entry)."""
    for i in range(len(P)):
        _probe_point(i, P, Q, members, cluster_support, support, planes, plane_start, reach, ratio, tol, with_planes,
                     low, PQ, upper, S, lower)


@helper
def _pq(x, y, z, Q, k):
    """``q_k . p`` of the point ``(x, y, z)``."""
    return x * Q[k, 0] + y * Q[k, 1] + z * Q[k, 2]


@helper
def _support_bound(pq0, pq1, pq2, pq3, support, j, ratio):
    """Piece j's support lower bound of cP at the point with ``q_k . p = pq_k``."""
    return ratio * max(max(pq0 - support[j, 0], pq1 - support[j, 1]), max(pq2 - support[j, 2], pq3 - support[j, 3]))


@kernel
def _group_probe(P, groups, Q, members, cluster_support, support, planes, plane_start, reach, ratio, tol, low, PQ,
                 upper, S, lower, smallest, cheap, far, floor, tight, keep):
    """`PieceIndex.group_probe` into the `Probe` arrays, ``floor`` and ``keep`` (``S``, ``lower``, ``smallest``,
    ``floor``, ``tight`` inf on entry).

    Stage 0, the points of a group with a finite ``far``: the support lower
    bound; a group whose smallest bound exceeds its ``far`` (within
    round-off) is dropped. Stage 1, the points of the other groups: the
    nearest-vertex upper bound and the support lower bound; a point whose
    lower bound exceeds its group's smallest upper bound (within round-off;
    the point attaining it is always kept) is dropped. Stage 2, the others:
    the facet planes too (inside a piece the bounds are ``(-inf, 0)``), and
    the same tests against the group's smallest upper bound, now also over
    the points inside a piece, and against its ``far`` (into ``tight``, per
    group: the smallest of these bounds over the points stage 1 kept, the
    group's cP being theirs).
    """
    n, J = len(P), len(support)
    support_only, with_planes = tol != tol, tol == tol  # not literals: numba would compile _probe_point once more
    for i in range(n):  # stage 0: the groups that the support bounds alone place beyond their far (no vertex search)
        g = groups[i]
        if far[g] < np.inf:
            x, y, z = P[i, 0], P[i, 1], P[i, 2]
            pq0, pq1, pq2, pq3 = _pq(x, y, z, Q, 0), _pq(x, y, z, Q, 1), _pq(x, y, z, Q, 2), _pq(x, y, z, Q, 3)
            for j in range(J):
                floor[g] = min(floor[g], _support_bound(pq0, pq1, pq2, pq3, support, j, ratio))
    for g in range(len(far)):
        if far[g] < np.inf and floor[g] > far[g] * (1 + tol) + tol:
            far[g] = -np.inf  # dropped
    for i in range(n):
        if far[groups[i]] == -np.inf:
            continue
        _probe_point(i, P, Q, members, cluster_support, support, planes, plane_start, reach, ratio, tol, support_only, low,
                     PQ, upper, S, lower)
        cheap[i] = np.inf
        for j in range(J):
            cheap[i] = min(cheap[i], lower[i, j])
            lower[i, j] = np.inf
        smallest[groups[i]] = min(smallest[groups[i]], upper[i])
        floor[groups[i]] = min(floor[groups[i]], cheap[i])
    for i in range(n):
        s, g = smallest[groups[i]], groups[i]
        keep[i] = floor[g] <= far[g] * (1 + tol) + tol and (cheap[i] <= s * (1 + tol) + tol or upper[i] == s)
    for i in range(n):
        if keep[i]:
            _probe_point(i, P, Q, members, cluster_support, support, planes, plane_start, reach, ratio, tol, with_planes, low,
                         PQ, upper, S, lower)
            for j in range(J):
                if S[i, j] <= 0.0:
                    smallest[groups[i]] = min(smallest[groups[i]], 0.0)
    for i in range(n):
        if not keep[i]:
            continue
        inside = False
        low_i = np.inf
        for j in range(J):
            inside = inside or S[i, j] <= 0.0
            low_i = min(low_i, lower[i, j])
        up_i = 0.0 if inside else upper[i]
        s = smallest[groups[i]]
        keep[i] = inside or low_i <= s * (1 + tol) + tol or up_i == s
        tight[groups[i]] = min(tight[groups[i]], -np.inf if inside else low_i)
    for g in range(len(far)):  # the facet planes' bound may place a group stage 1 kept beyond its far
        if tight[g] > far[g] * (1 + tol) + tol and tight[g] < np.inf:
            floor[g] = max(floor[g], tight[g])
            far[g] = -np.inf  # dropped
    for i in range(n):
        keep[i] = keep[i] and far[groups[i]] > -np.inf
