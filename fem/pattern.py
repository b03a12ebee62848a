"""A fixed sparsity pattern: scatter batches of element matrices into a CSR matrix fast.

Element contributions come as groups of items (elements, facets, fiber segments). A group is

- a dof array `dofs` of shape (n_local, n_items): square blocks, rows and columns the same dofs;
- a pair (row_dofs, col_dofs) of shapes (n_rows, n_items) and (n_cols, n_items): rectangular
  blocks;
- a `Mirrored` group: entries that are assembled at (row, col) *and* at (col, row) (once where
  row == col). A symmetric element matrix needs only its upper triangle (`Mirrored.upper`), and
  an off-diagonal block of a symmetric element matrix stands for its transpose too
  (`Mirrored.block`): about half the values to compute and to scatter.

Dof numbers are global, or -1 for an entry to drop, such as a Dirichlet dof. The values of a
block group come as an array (n_items, n_rows, n_cols), those of a `Mirrored` group as
(n_items, n_entries). The pattern is built once by sorting the linear keys
row * n + col; each assembly is then a `np.bincount` of the values into CSR data order (one for
the mirrored groups, into the upper triangle, spread to both triangles by one gather; one for
the others). Rows/columns are the free dofs only: Dirichlet dofs are condensed out by the caller's
`free_index` map (global dof -> free number, -1).

The values of all groups form one flat array of `size` entries. A caller that assembles
repeatedly can keep such an array (`new_values`), write each group's values into its view
(`views`) and scatter it with `assemble_values`; this saves the concatenation of `assemble` (a full
copy of the values, as expensive as the scatter itself).

Tied dofs (`fem.dirichlet`, a dof s that is sum_j c_sj x_mj of free dofs m_j) come as `links`:
the pattern then assembles T^T K T. An entry (r, c) on a tied row or column has free number -1
(dropped by the main scatter) and is re-entered at (m_r, m_c) with weight c_r c_c for each pair
of masters (a free dof is its own master with weight 1); a `Mirrored` entry is re-entered in
both orientations (once on the element's diagonal). Few entries touch a cut: their gather and
scatter cost little.

The pattern also knows its transpose permutation (a symmetry check costs one gather) and its upper
triangle (the input of symmetric solvers), also of the symmetric part (A + A^T) / 2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp


@dataclass(frozen=True)
class Mirrored:
    """Entries e of item j assembled at (rows[e, j], cols[e, j]) and at the transposed position."""

    rows: np.ndarray  # (n_entries, n_items) global dofs
    cols: np.ndarray

    @classmethod
    def upper(cls, dofs: np.ndarray) -> Mirrored:
        """The upper triangle (r <= c, row by row, `np.triu_indices`) of square blocks on `dofs`."""
        r, c = np.triu_indices(dofs.shape[0])
        return cls(dofs[r], dofs[c])

    @classmethod
    def block(cls, row_dofs: np.ndarray, col_dofs: np.ndarray) -> Mirrored:
        """All entries of (n_rows, n_cols) blocks, row by row; each also stands for its transpose."""
        nr, nc = row_dofs.shape[0], col_dofs.shape[0]
        return cls(np.repeat(row_dofs, nc, axis=0), np.tile(col_dofs, (nr, 1)))


def unique_inverse(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(unique, inverse) of integer keys, unique[inverse] == keys, by one argsort. Not
    `np.unique`: numpy >= 2.3 answers it for integers with a hash table, which took 3.5 s on the
    6.7M keys of the default ePSA mesh against 0.06 s for a sort."""
    order = np.argsort(keys)
    s = keys[order]
    keep = np.empty(s.size, dtype=bool)
    keep[:1] = True
    np.not_equal(s[1:], s[:-1], out=keep[1:])
    inverse = np.empty(keys.size, dtype=np.int64)
    inverse[order] = np.cumsum(keep) - 1
    return s[keep], inverse


def _linked(free_index, links, groups, order, shapes):
    """The re-entered entries of the tied dofs (module docstring): (flat value index, row, col,
    weight), rows and columns in free numbers. `order` is the groups' flat value order."""
    slaves, masters, coefs = links
    k = masters.shape[1]
    which = np.full(free_index.size, -1, dtype=np.int64)
    which[slaves] = np.arange(slaves.size)
    # every dof's masters and weights: itself (weight 1) if free, none if prescribed, a tied one's
    own = free_index  # -1 for a prescribed or tied dof
    out, start = [], 0
    for g in order:
        group = groups[g]
        if isinstance(group, Mirrored):
            r, c = group.rows.T, group.cols.T  # (n_items, n_entries), the flat order
            pairs = [(r, c), (c, r)]
        else:
            rd, cd = group if isinstance(group, tuple) else (group, group)
            shape = shapes[g]
            r = np.broadcast_to(rd.T[:, :, None], shape)
            c = np.broadcast_to(cd.T[:, None, :], shape)
            pairs = [(r, c)]
        index = start + np.arange(r.size).reshape(r.shape)
        for n, (rr, cc) in enumerate(pairs):
            hit = (which[rr] >= 0) | (which[cc] >= 0)
            if n == 1:
                hit &= rr != cc  # a mirrored diagonal entry stands once
            if hit.any():
                out.append((index[hit], rr[hit], cc[hit]))
        start += r.size
    if not out:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0)
    src, rows, cols = (np.concatenate(a) for a in zip(*out))

    def expand(dofs):
        s = which[dofs]
        m = np.where(s[:, None] >= 0, masters[np.maximum(s, 0)], -1)
        w = np.where(s[:, None] >= 0, coefs[np.maximum(s, 0)], 0.0)
        m[:, 0] = np.where(s >= 0, m[:, 0], own[dofs])
        w[:, 0] = np.where(s >= 0, w[:, 0], (own[dofs] >= 0).astype(float))
        return m, w

    (mr, wr), (mc, wc) = expand(rows), expand(cols)
    R, C = np.repeat(mr, k, axis=1), np.tile(mc, (1, k))
    W = np.repeat(wr, k, axis=1) * np.tile(wc, (1, k))
    keep = (R >= 0) & (C >= 0) & (W != 0)
    return np.broadcast_to(src[:, None], R.shape)[keep], R[keep], C[keep], W[keep]


class Pattern:
    def __init__(self, free_index: np.ndarray, groups: list, links=None):
        self.n = int(free_index.max()) + 1
        n = self.n
        self.shapes = []  # value shape of each group, in the caller's order
        mirrored, plain = [], []  # (group index, rows, cols) with rows/cols (n_items, ...)
        for g, group in enumerate(groups):
            if isinstance(group, Mirrored):
                rows, cols = free_index[group.rows].T, free_index[group.cols].T  # (n_items, n_entries)
                self.shapes.append(rows.shape)
                mirrored.append((g, rows, cols))
            else:
                row_dofs, col_dofs = group if isinstance(group, tuple) else (group, group)
                r, c = free_index[row_dofs].T, free_index[col_dofs].T
                shape = (r.shape[0], r.shape[1], c.shape[1])
                self.shapes.append(shape)
                plain.append(
                    (g, np.broadcast_to(r[:, :, None], shape), np.broadcast_to(c[:, None, :], shape))
                )

        def keys(rows, cols):
            # entries in a Dirichlet row or column get key -1: they go to a discard bin
            rows = rows.reshape(-1).astype(np.int64, copy=False)
            cols = cols.reshape(-1).astype(np.int64, copy=False)
            return np.where((rows >= 0) & (cols >= 0), rows * n + cols, -1)

        # Flat value layout: the mirrored groups first, then the others.
        self._order = [g for g, _, _ in mirrored] + [g for g, _, _ in plain]
        self.size = sum(int(np.prod(self.shapes[g])) for g in self._order)
        m = self._n_mirrored = sum(int(np.prod(self.shapes[g])) for g, _, _ in mirrored)
        # One argsort of every key (each mirrored entry at (r, c) and at (c, r)) gives the CSR
        # pattern and every entry's position in it; a searchsorted per entry took 19 s of the
        # 54 s set-up at 165k DOFs (loaded machine).
        every = [keys(r, c) for _, r, c in mirrored] + [keys(c, r) for _, r, c in mirrored]
        every += [keys(r, c) for _, r, c in plain]
        has_links = links is not None and links[0].size > 0
        if has_links:
            src, lr, lc, lw = _linked(free_index, links, groups, self._order, self.shapes)
            every.append(lr * n + lc)
        values, inverse = unique_inverse(np.concatenate(every)) if every else (np.zeros(0, np.int64),) * 2
        del every
        discard = int(values.size > 0 and values[0] < 0)
        unique = values[discard:]
        self.nnz = unique.size
        position = inverse - discard
        position[position < 0] = self.nnz  # discarded entries -> the bin after the last position
        del inverse
        lower = (
            np.concatenate([(r > c).reshape(-1) for _, r, c in mirrored]) if mirrored else np.zeros(0, bool)
        )
        # mirrored values go to the position of (min, max), in the upper triangle
        self._inverse_mirrored = np.where(lower, position[m : 2 * m], position[:m])
        # The other groups touch few positions (facets, fiber segments): their bincount runs
        # over those positions only and is added there.
        n_plain = self.size - m
        self._plain_positions, self._inverse = unique_inverse(position[2 * m : 2 * m + n_plain])
        self._links = (src, position[2 * m + n_plain :], lw) if has_links else None
        del position
        col = unique % n
        row = unique // n
        self.indices = col.astype(np.int32)
        self.indptr = np.searchsorted(row, np.arange(n + 1)).astype(np.int32)
        # Transpose map: data[transpose] is the data of A^T in this pattern (the pattern is
        # structurally symmetric: element blocks are square in the same dofs, rectangular groups
        # come with their transposed partner, mirrored groups hold both).
        positions_of = sp.csr_matrix((np.arange(self.nnz), self.indices, self.indptr), shape=(n, n))
        self._transpose = positions_of.T.tocsr().data  # CSR of A^T lists A's positions (sorted rows)
        upper = col >= row
        self._canonical = np.where(upper, np.arange(self.nnz), self._transpose)  # position of (min, max)
        self._upper = np.flatnonzero(upper)
        self._upper_indices = self.indices[upper]
        self._upper_indptr = np.searchsorted(row[upper], np.arange(n + 1)).astype(np.int32)

    def new_values(self) -> np.ndarray:
        """An uninitialised flat value array for all groups (fill it through `views`)."""
        return np.empty(self.size)

    def views(self, values: np.ndarray) -> list[np.ndarray]:
        """The value array of every group (in the order of the groups given) inside `values`."""
        out, start = [None] * len(self.shapes), 0
        for g in self._order:
            stop = start + int(np.prod(self.shapes[g]))
            out[g] = values[start:stop].reshape(self.shapes[g])
            start = stop
        return out

    def assemble(self, blocks: list[np.ndarray]) -> sp.csr_matrix:
        """`blocks[g]` has the value shape of group g: (n_items, n_rows, n_cols) for blocks (items
        first, so element matrices are written in place without a transposed copy), (n_items,
        n_entries) for `Mirrored` groups."""
        return self.assemble_values(np.concatenate([blocks[g].reshape(-1) for g in self._order]))

    def assemble_values(self, values: np.ndarray) -> sp.csr_matrix:
        """CSR matrix of a flat value array (all groups; see `views`)."""
        m = self._n_mirrored
        if m:
            upper = np.bincount(self._inverse_mirrored, weights=values[:m], minlength=self.nnz + 1)
            data = upper[self._canonical]
        else:
            data = np.zeros(self.nnz)
        if self.size > m:
            sums = np.bincount(self._inverse, weights=values[m:], minlength=self._plain_positions.size)
            keep = self._plain_positions < self.nnz  # drop the discard bin
            data[self._plain_positions[keep]] += sums[keep]
        if self._links is not None:
            src, pos, w = self._links
            data += np.bincount(pos, weights=values[src] * w, minlength=self.nnz)
        A = sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))
        A.pattern = self
        return A

    def asymmetry(self, A) -> float:
        """max |A - A^T| / max |A| (a gather over the data, no transposition)."""
        d = A.data
        return float(np.abs(d - d[self._transpose]).max() / max(np.abs(d).max(), 1e-300))

    def symmetric_part_upper(self, A) -> sp.csr_matrix:
        """Upper triangle of the symmetric part (A + A^T) / 2 in CSR (two gathers)."""
        d = A.data[self._upper]
        return sp.csr_matrix(
            (0.5 * (d + A.data[self._transpose[self._upper]]), self._upper_indices, self._upper_indptr),
            shape=(self.n, self.n),
        )

    def upper(self, A) -> sp.csr_matrix:
        """Upper triangle (diagonal included) of A in CSR, for symmetric solvers."""
        return sp.csr_matrix(
            (A.data[self._upper], self._upper_indices, self._upper_indptr), shape=(self.n, self.n)
        )
