"""The influence matrix of the march as a function of the patch half-length a(t): the exact rebuild
(rail.contact.basis._closure_matrix) or an interpolation table of it (issue 44; docs/contact.md,
"The influence matrix between rebuilds").

Within one lead cell (the leading loaded node ``lead`` fixed; e = a / Delta - (lead - M) in (0, 1], the
edge's place in its cell) the influence matrix C, its rows r_edge, r_trail at xi = +-a and the
column weights w vary smoothly with a except for square-root behaviour at both ends of the cell: the
columns of the outermost loaded nodes carry the factor 1 / W(xi_lead) ~ 1 / sqrt(e), and their
integrals against rows near the edge terms in e^(3/2) (ln e) and (1 - e)^(3/2) ln(1 - e). With the
variable theta = asin(sqrt(e)) in [0, pi/2] (sqrt(e) = sin theta, sqrt(1 - e) = cos theta) and the
singular factor taken out (the two outermost columns times sqrt(e)), what is left is smooth to
theta^3 ln theta at the ends: it is interpolated by barycentric Chebyshev interpolation in
x = 2 theta / pi, on _TABLE_PIECES equal pieces of [0, 1] with _TABLE_NODES first-kind Chebyshev
nodes each (tabulated by exact rebuilds, for the lead cells a march visits). Measured against the
exact rebuild: 2e-10 of the largest entry of the loaded columns (tests/test_influence_table.py).

The march chooses by ``influence``: 'table' (the default) or 'exact'. A march whose distinct values of
a are fewer than the table's rebuilds is rebuilt exactly even with 'table' (a fixed a is one rebuild).
"""

from __future__ import annotations

import math

import numpy as np

from .._lazyjit import njit
from .basis import _closure_matrix, _influence_arrays

__all__ = ["INFLUENCE", "influence_table", "table_cells"]

INFLUENCE = ("table", "exact")  # how the march gets the influence matrix at a(t)
_TABLE_NODES = 6  # first-kind Chebyshev nodes per piece
_TABLE_PIECES = 16  # equal pieces of x = 2 asin(sqrt(e)) / pi in [0, 1]


def _chebyshev_first_kind(m: int):
    """First-kind Chebyshev nodes on [0, 1] (increasing) and their barycentric weights."""
    th = np.pi * (2 * np.arange(m) + 1) / (2 * m)
    return np.ascontiguousarray(0.5 * (1 - np.cos(th))), np.ascontiguousarray((-1.0) ** np.arange(m) * np.sin(th))


@njit(cache=True)
def _lead_cell(ai, delta, M):
    """The leading loaded node of the patch at half-length ai and the edge's place e in (0, 1] in its
    cell (as rail.contact.basis._basis_matrix)."""
    at = ai / delta
    lead = int(math.floor(at - 1e-12)) + M
    return lead, at - (lead - M)


def table_cells(a, delta: float, M: int, nodes: int | None = None, pieces: int | None = None):
    """The lead cells a march tabulates: every cell a visits if its distinct half-lengths outnumber the
    table's rebuilds (nodes x pieces per cell), else none (a fixed a is one exact rebuild). All or none:
    a small change of the inputs leaves the choice as it is, so that the march stays a smooth function
    of them (a finite difference of it does not mix the table with the exact rebuild).

    Parameters
    ----------
    a : ndarray
        Half-length at each step [m].
    delta : float
        Grid spacing [m].
    M : int
        Index of the centre node [-].
    nodes, pieces : int, optional
        Chebyshev nodes per piece and pieces per cell [-]; default _TABLE_NODES, _TABLE_PIECES.

    Returns
    -------
    ndarray of int64
        The lead nodes of the cells to tabulate, increasing.
    """
    nodes = _TABLE_NODES if nodes is None else nodes
    pieces = _TABLE_PIECES if pieces is None else pieces
    a = np.unique(np.asarray(a, dtype=float))
    if a.size == 0:
        return np.zeros(0, dtype=np.int64)
    cells = np.unique(np.floor(a / delta - 1e-12).astype(np.int64) + M)
    if a.size <= nodes * pieces * cells.size:  # fewer rebuilds without the table
        return np.zeros(0, dtype=np.int64)
    return np.ascontiguousarray(cells, dtype=np.int64)


@njit(cache=True)
def _build_table(cells, x0, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, ws, pieces):
    """The tables of the influence matrix for the lead cells ``cells`` (exact rebuilds at the nodes x0
    of each of ``pieces`` pieces of x = 2 asin(sqrt(e)) / pi; the two outermost loaded columns times
    sqrt(e)). Returns (T, Re, Rt, W, slot): T[(c pieces + j) m + i] the flattened C at node i of piece j
    of cell c, Re, Rt, W its r_edge, r_trail, w likewise; slot[lead] the cell's index (-1: none)."""
    nn = xi.size
    m = x0.size
    nt = cells.size * pieces * m
    T = np.empty((nt, (nn + 1) * nn))
    Re = np.empty((nt, nn))
    Rt = np.empty((nt, nn))
    W = np.empty((nt, nn))
    slot = np.full(nn + 1, -1, dtype=np.int64)
    C, r_edge, r_trail, w, AT, r_a, wu = _influence_arrays(nn)
    for c in range(cells.size):
        slot[cells[c]] = c
        for j in range(pieces):
            for i in range(m):
                se = math.sin(0.5 * math.pi * (j + x0[i]) / pieces)  # sqrt(e) at the node
                ai = delta * (cells[c] - M + se * se)
                lead, trail = _closure_matrix(ai, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge,
                                              w, r_trail, AT, r_a, wu, ws)
                if lead != cells[c]:
                    raise ValueError("a table node fell outside its lead cell")
                row = (c * pieces + j) * m + i
                Tr = T[row]
                for r in range(nn + 1):
                    for n in range(nn):
                        f = se if (n == lead or n == trail) else 1.0
                        Tr[r * nn + n] = C[r, n] * f
                for n in range(nn):
                    f = se if (n == lead or n == trail) else 1.0
                    Re[row, n] = r_edge[n] * f
                    Rt[row, n] = r_trail[n] * f
                    W[row, n] = w[n] * f
    return T, Re, Rt, W, slot


@njit(cache=True)
def _barycentric(x, x0, bw, l, dl):
    """The barycentric interpolation weights l at x (and their derivatives dl in x) on the nodes x0
    with the barycentric weights bw (in place)."""
    m = x0.size
    hit = -1
    for i in range(m):
        if x == x0[i]:
            hit = i
    if hit >= 0:  # at a node: the unit vector, and the differentiation matrix's row
        tot = 0.0
        for i in range(m):
            l[i] = 1.0 if i == hit else 0.0
            dl[i] = 0.0 if i == hit else (bw[i] / bw[hit]) / (x0[hit] - x0[i])
            tot += dl[i]
        dl[hit] = -tot
        return
    s1 = 0.0
    s2 = 0.0
    for i in range(m):
        t = bw[i] / (x - x0[i])
        l[i] = t
        s1 += t
        s2 += t / (x - x0[i])
    for i in range(m):
        dl[i] = l[i] / s1 * (s2 / s1 - 1.0 / (x - x0[i]))
        l[i] /= s1


@njit(cache=True)
def _table_place(ai, delta, M, pieces):
    """Where a is in its cell's table: (lead, e, piece j, the local x in [0, 1] of the piece, dx/da
    [1/m] of the local x)."""
    lead, e = _lead_cell(ai, delta, M)
    se = math.sqrt(min(e, 1.0))
    th = math.asin(se)
    x = 2.0 * th / math.pi * pieces
    j = min(int(x), pieces - 1)
    # d(local x)/da = pieces (2 / pi) / cos(theta) / (2 sqrt(e)) / delta
    dxda = pieces / (math.pi * max(math.cos(th), 1e-300) * max(se, 1e-300) * delta)
    return lead, e, j, x - j, dxda


@njit(cache=True)
def _table_eval(row0, l, T, Re, Rt, W, C, r_edge, w, r_trail):
    """C, r_edge, w, r_trail = sum_i l[i] (the table rows row0 + i) (in place; unscaled columns)."""
    nn = w.size
    m = l.size
    Cf = C.reshape((nn + 1) * nn)
    if m == 6:  # the table's nodes (_TABLE_NODES): one pass over the entries, the terms in the nodes' order
        T0, T1, T2, T3, T4, T5 = T[row0], T[row0 + 1], T[row0 + 2], T[row0 + 3], T[row0 + 4], T[row0 + 5]
        l0, l1, l2, l3, l4, l5 = l[0], l[1], l[2], l[3], l[4], l[5]
        for q in range(Cf.size):
            Cf[q] = l0 * T0[q] + l1 * T1[q] + l2 * T2[q] + l3 * T3[q] + l4 * T4[q] + l5 * T5[q]
    else:
        for q in range(Cf.size):
            Cf[q] = 0.0
        for i in range(m):
            li = l[i]
            Tr = T[row0 + i]
            for q in range(Cf.size):
                Cf[q] += li * Tr[q]
    for n in range(nn):
        ae, at, aw = 0.0, 0.0, 0.0
        for i in range(m):
            ae += l[i] * Re[row0 + i, n]
            at += l[i] * Rt[row0 + i, n]
            aw += l[i] * W[row0 + i, n]
        r_edge[n], r_trail[n], w[n] = ae, at, aw


@njit(cache=True)
def _unscale(lead, trail, se, C, r_edge, w, r_trail):
    """Divide the two outermost loaded columns by sqrt(e) (in place)."""
    inv = 1.0 / se
    for r in range(C.shape[0]):
        C[r, lead] *= inv
        C[r, trail] *= inv
    for n in (lead, trail):
        r_edge[n] *= inv
        r_trail[n] *= inv
        w[n] *= inv


@njit(cache=True)
def _influence_at(ai, table, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w, r_trail, AT, r_a,
                  wu, ws, l, dl):
    """The influence matrix at ai (C, r_edge, w, r_trail in place): from the table where its cell is
    tabulated, else the exact rebuild (rail.contact.basis._closure_matrix). table: (T, Re, Rt, W, slot,
    x0, bw, pieces) of _build_table; l, dl: work arrays of the table's nodes. Returns (lead, trail)."""
    T, Re, Rt, W, slot, x0, bw, pieces = table
    lead, e, j, x, _ = _table_place(ai, delta, M, pieces)
    if lead < slot.size and slot[lead] >= 0:
        _barycentric(x, x0, bw, l, dl)
        _table_eval((slot[lead] * pieces + j) * x0.size, l, T, Re, Rt, W, C, r_edge, w, r_trail)
        trail = 2 * M - lead
        _unscale(lead, trail, math.sqrt(e), C, r_edge, w, r_trail)
        return lead, trail
    return _closure_matrix(ai, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, C, r_edge, w, r_trail, AT,
                           r_a, wu, ws)


@njit(cache=True)
def _influence_d_at(ai, table, C, r_edge, w, r_trail, Cd, r_edge_d, r_trail_d, C2, r_edge2, w2, r_trail2, delta, M, l, dl):
    """The table's influence matrix at ai and its derivative in a (Cd, r_edge_d, r_trail_d [1/m of the
    entries]; in place): the derivative of the interpolant, with the singular factor 1 / sqrt(e) of the
    two outermost loaded columns differentiated exactly. C2, r_edge2, w2, r_trail2: work arrays. The
    cell must be tabulated. Returns (lead, trail)."""
    T, Re, Rt, W, slot, x0, bw, pieces = table
    lead, e, j, x, dxda = _table_place(ai, delta, M, pieces)
    trail = 2 * M - lead
    row0 = (slot[lead] * pieces + j) * x0.size
    _barycentric(x, x0, bw, l, dl)
    _table_eval(row0, l, T, Re, Rt, W, C, r_edge, w, r_trail)  # the scaled values
    _table_eval(row0, dl, T, Re, Rt, W, C2, r_edge2, w2, r_trail2)  # their derivatives in the local x
    nn = w.size
    for r in range(nn + 1):
        for n in range(nn):
            Cd[r, n] = C2[r, n] * dxda
    for n in range(nn):
        r_edge_d[n] = r_edge2[n] * dxda
        r_trail_d[n] = r_trail2[n] * dxda
    # the outermost columns are F / sqrt(e): d/da = F' / sqrt(e) - F / (2 e^(3/2) delta)
    se = math.sqrt(e)
    g = 0.5 / (e * delta)
    for n in (lead, trail):
        for r in range(nn + 1):
            Cd[r, n] = Cd[r, n] / se - C[r, n] / se * g
        r_edge_d[n] = r_edge_d[n] / se - r_edge[n] / se * g
        r_trail_d[n] = r_trail_d[n] / se - r_trail[n] / se * g
    _unscale(lead, trail, se, C, r_edge, w, r_trail)
    return lead, trail


def influence_table(a, Mom, mu, xi, k: float, delta: float, M: int, closure: int, closure_scale: float, report_coef: float,
                    ws, influence: str = "table"):
    """The march's table of the influence matrix (the argument ``table`` of _influence_at).

    Parameters
    ----------
    a : ndarray
        The half-length at each step of the march [m].
    Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, ws
        As rail.contact.basis._closure_matrix (closure 0: default, 1: report).
    influence : str
        'table' (tabulate the cells of table_cells) or 'exact' (no cell: every step is rebuilt).

    Returns
    -------
    tuple
        (T, Re, Rt, W, slot, x0, bw, pieces).
    """
    if influence not in INFLUENCE:
        raise ValueError(f"influence = {influence!r} is not allowed: it must be one of {list(INFLUENCE)}.")
    nodes, pieces = _TABLE_NODES, _TABLE_PIECES
    x0, bw = _chebyshev_first_kind(nodes)
    cells = table_cells(a, delta, M, nodes, pieces) if influence == "table" else np.zeros(0, dtype=np.int64)
    T, Re, Rt, W, slot = _build_table(cells, x0, Mom, mu, xi, k, delta, M, closure, closure_scale, report_coef, ws, pieces)
    return T, Re, Rt, W, slot, x0, bw, pieces
