"""The labelling of basins of attraction between chunks of map iterations, compiled by numba.

:mod:`lagrangian.ensemble.basins` integrates the members still searching by a chunk of
iterations of the map (the strobe map, or the flow sampled at a fixed interval) and
hands the new points here: :func:`label` walks each member's points in order, member
after member (not in parallel: a cell one member labels is seen by the next one at once,
so two members converging together find one attractor, not two), through the recurrence
state machine of Attractors.jl's ``AttractorsViaRecurrences``:

- a point outside the box of cells for ``lost`` iterations in a row: no attractor (-1);
- a point in a cell of attractor k for ``hits`` iterations in a row: attractor k;
- a point in a cell last visited by a start that has since been labelled k (a cell of
  k's basin), for ``basin_hits`` iterations in a row: attractor k (most starts end so,
  long before they are near the attractor: Attractors.jl's basin cells);
- a point in a cell the member itself visited counts one recurrence; after
  ``recurrences`` of them the member is on an attractor not yet known: it gets the next
  label and goes on ``locate`` more iterations, marking each cell it lands in as that
  attractor's and keeping the points (for the attractor's period and representative
  points);
- ``max_iterations`` iterations without any of that, or a point that is not finite: -1.

A cell holds -1 (never visited), k >= 0 (a cell of attractor k), or -(id + 2): a member
(by its id, the place of its start in the order the starts are taken) that visited it
while searching; a member that finds its own mark there has been there before.  The mark
of a member since labelled k makes the cell one of k's basin; the mark of a member
labelled -1, or of one still searching that was taken after this one, is taken over (the
cell is new to this one); the mark of one still searching that was taken before it is
left alone.  So the earliest start still searching runs as it would alone, as each start
does in Attractors.jl, which runs them one after another: members that share the cells of
one orbit cannot keep wiping each other's marks (with a chunk of iterations no longer
than the orbit's period none of them would ever see its own mark again).  The module goes
into the code cache as it is (``package_text``), where numba keeps its machine code;
importing :mod:`lagrangian.ensemble.basins` does not import it.
"""

import math

from numba import njit

#: A member's status: still searching, locating a new attractor, or done (>= 0, -1).
SEARCHING = -2
LOCATING = -3


@njit(cache=True)
def cell_of(point, which, lows, widths, sizes, angles, centres):  # pragma: no cover
    """The flat index of the cell of ``point`` (the state), -1 outside the box, -2 not finite."""
    index = 0
    for d in range(which.shape[0]):
        x = point[which[d]]
        if x != x or math.isinf(x):
            return -2
        if angles[d]:
            x = centres[d] - math.pi + (x - centres[d] + math.pi) % (2 * math.pi)
        k = math.floor((x - lows[d]) / widths[d] + 0.5)
        if k < 0 or k >= sizes[d]:
            return -1
        index = index * sizes[d] + k
    return index


@njit(cache=True)
def root(alias, k):  # pragma: no cover - compiled by numba
    """The attractor that attractor k was found to be (itself, unless merged)."""
    while alias[k] != k:
        k = alias[k]
    return k


@njit(cache=True)
def run_length(counters, b, run, value):  # pragma: no cover - compiled by numba
    """Start b's run of iterations in a row on ``value``: column ``run`` counts it, column
    ``run + 1`` holds the value; a new value starts a new run of 1."""
    if counters[b, run] > 0 and counters[b, run + 1] == value:
        counters[b, run] += 1
    else:
        counters[b, run] = 1
        counters[b, run + 1] = value
    return counters[b, run]


@njit(cache=True)
def label(
    points, ids, status, counters, cells, which, lows, widths, sizes, angles, centres,
    settings, found, kept, alias, done,
):  # pragma: no cover - compiled by numba  # fmt: skip
    """Walk the new points (B, m, C) of the B members in order (see the module).

    ``status`` (B,): per member SEARCHING, LOCATING, a label >= 0 or -1; ``counters``
    (B, 7): iterations, recurrences, hits in a row, the label hit, iterations outside
    in a row, basin hits in a row, the basin hit (while locating: the points kept in the
    second, the new label in the fourth); ``settings``: recurrences, hits, lost,
    max_iterations, locate, basin hits; ``done`` (every start's id): the label of each
    start done, else < 0; ``found`` (1,): the attractors so far; ``kept``
    (A, locate, m): each attractor's located points (a member past A attractors gets -1);
    ``alias`` (A,): the attractor each is (a new one that lands in the cells of one found
    before is that one: one attractor found by two members at once, from two of its
    cells, is merged as soon as either sees the other's cells).
    """
    recurrences, hits, lost, limit, locate, basin_hits = (
        settings[0], settings[1], settings[2], settings[3], settings[4], settings[5]
    )  # fmt: skip
    capacity = kept.shape[0]
    count, m, chunk = points.shape
    for b in range(count):
        mark = -(ids[b] + 2)
        for j in range(chunk):
            state = status[b]
            if state >= -1:
                break
            point = points[b, :, j]
            counters[b, 0] += 1
            if state == SEARCHING and counters[b, 0] > limit:
                status[b] = -1  # the check at the end is skipped by the paths that continue
                break
            cell = cell_of(point, which, lows, widths, sizes, angles, centres)
            if cell == -2:
                status[b] = -1
                break
            if state == LOCATING:
                new = counters[b, 3]
                if cell >= 0 and cells[cell] < 0:
                    cells[cell] = new
                elif cell >= 0:
                    mine, other = root(alias, new), root(alias, cells[cell])
                    if mine != other:
                        alias[max(mine, other)] = min(mine, other)
                at = counters[b, 1]
                for i in range(m):
                    kept[new, at, i] = point[i]
                counters[b, 1] = at + 1
                if at + 1 >= locate:
                    status[b] = new
                continue
            if cell == -1:
                counters[b, 2] = 0
                counters[b, 5] = 0
                counters[b, 4] += 1
                if counters[b, 4] >= lost:
                    status[b] = -1
                    break
            else:
                counters[b, 4] = 0
                value = cells[cell]
                if value >= 0:
                    counters[b, 5] = 0
                    value = root(alias, value)
                    if run_length(counters, b, 2, value) >= hits:
                        status[b] = value
                        break
                else:
                    counters[b, 2] = 0
                    owner = -value - 2
                    basin = root(alias, done[owner]) if value <= -2 and done[owner] >= 0 else -1
                    if basin >= 0 and value != mark:
                        if run_length(counters, b, 5, basin) >= basin_hits:
                            status[b] = basin
                            break
                        continue
                    counters[b, 5] = 0
                    if value <= -2 and value != mark and -value - 2 < ids[b] and done[owner] == -2:
                        continue  # an earlier start, still searching, keeps its mark
                    if value == mark:
                        counters[b, 1] += 1
                        if counters[b, 1] >= recurrences:
                            new = found[0]
                            if new >= capacity:
                                status[b] = -1
                                break
                            found[0] = new + 1
                            cells[cell] = new
                            for i in range(m):
                                kept[new, 0, i] = point[i]
                            status[b] = LOCATING
                            counters[b, 1] = 1
                            counters[b, 3] = new
                            if locate <= 1:
                                status[b] = new
                            continue
                    else:
                        cells[cell] = mark
            if counters[b, 0] >= limit:
                status[b] = -1
                break
