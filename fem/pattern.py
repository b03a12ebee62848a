"""A fixed sparsity pattern: scatter batches of element matrices into a CSR matrix fast.

Element contributions come as groups. A group is either a dof array `dofs` of shape
(n_local, n_items) (square blocks: rows and columns are the same dofs) or a pair
(row_dofs, col_dofs) of shapes (n_rows, n_items) and (n_cols, n_items) (rectangular blocks, such
as the displacement-pressure coupling of a mixed element). Dof numbers are global, or -1 for an
entry to drop, such as a Dirichlet dof. The values of group g come as an array (n_items, n_rows,
n_cols). The pattern is built once with `np.unique` over the linear keys row * n + col; each
assembly is then a single `np.bincount` of the element values into CSR data order. Rows/columns
are the free dofs only: Dirichlet dofs are condensed out by the caller's `free_index` map (global
dof -> free number, -1).

The values of all groups, concatenated, form one flat array of `size` entries. A caller that
assembles repeatedly can keep such an array (`new_values`), write each group's element matrices
into its view (`views`) and scatter it with `assemble_values`, which saves the concatenation of
`assemble` (a full copy of the values, as expensive as the scatter itself).

The pattern also knows its transpose permutation (a symmetry check costs one gather) and its upper
triangle (the input of symmetric solvers).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp


class Pattern:
    def __init__(self, free_index: np.ndarray, groups: list):
        self.n = int(free_index.max()) + 1
        keys = []
        self.shapes = []                               # (n_items, n_rows, n_cols) per group
        for group in groups:
            row_dofs, col_dofs = group if isinstance(group, tuple) else (group, group)
            rows = free_index[row_dofs].T                 # (n_items, n_rows)
            cols = free_index[col_dofs].T                 # (n_items, n_cols)
            n_items, n_rows = rows.shape
            n_cols = cols.shape[1]
            self.shapes.append((n_items, n_rows, n_cols))
            r = np.broadcast_to(rows[:, :, None], (n_items, n_rows, n_cols)).reshape(-1)
            c = np.broadcast_to(cols[:, None, :], (n_items, n_rows, n_cols)).reshape(-1)
            # entries in a Dirichlet row or column get key -1: they go to a discard bin
            key = np.where((r >= 0) & (c >= 0), r.astype(np.int64) * self.n + c, -1)
            keys.append(key)
        all_keys = np.concatenate(keys)
        self.size = all_keys.size
        unique, inverse = np.unique(all_keys, return_inverse=True)
        dropped = unique.size > 0 and unique[0] == -1
        if dropped:                      # bin 0 is the discard bin: shift it to the end
            unique = unique[1:]
            inverse = np.where(inverse == 0, unique.size, inverse - 1)
        self._inverse = inverse.reshape(-1)
        self.nnz = unique.size
        col = unique % self.n
        row = unique // self.n
        self.indices = col.astype(np.int32)
        self.indptr = np.searchsorted(row, np.arange(self.n + 1)).astype(np.int32)
        # Transpose map: data[transpose] is the data of A^T in this pattern (the pattern is
        # structurally symmetric: element blocks are square in the same dofs, and rectangular
        # groups come with their transposed partner).
        self._transpose = np.searchsorted(unique, col * self.n + row)
        upper = col >= row
        self._upper = np.flatnonzero(upper)
        self._upper_indices = self.indices[upper]
        self._upper_indptr = np.searchsorted(row[upper], np.arange(self.n + 1)).astype(np.int32)

    def new_values(self) -> np.ndarray:
        """An uninitialised flat value array for all groups (fill it through `views`)."""
        return np.empty(self.size)

    def views(self, values: np.ndarray) -> list[np.ndarray]:
        """The (n_items, n_rows, n_cols) view of every group in the flat array `values`."""
        out, start = [], 0
        for shape in self.shapes:
            stop = start + int(np.prod(shape))
            out.append(values[start:stop].reshape(shape))
            start = stop
        return out

    def assemble(self, blocks: list[np.ndarray]) -> sp.csr_matrix:
        """`blocks[g]` has shape (n_items, n_rows, n_cols) for group g (items first, so element
        matrices are written in place without a transposed copy)."""
        return self.assemble_values(np.concatenate([b.reshape(-1) for b in blocks]))

    def assemble_values(self, values: np.ndarray) -> sp.csr_matrix:
        """CSR matrix of a flat value array (all groups, in order; see `views`)."""
        data = np.bincount(self._inverse, weights=values, minlength=self.nnz + 1)[: self.nnz]
        A = sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))
        A.pattern = self
        return A

    def asymmetry(self, A) -> float:
        """max |A - A^T| / max |A| (a gather over the data, no transposition)."""
        d = A.data
        return float(np.abs(d - d[self._transpose]).max() / max(np.abs(d).max(), 1e-300))

    def upper(self, A) -> sp.csr_matrix:
        """Upper triangle (diagonal included) of A in CSR, for symmetric solvers."""
        return sp.csr_matrix((A.data[self._upper], self._upper_indices, self._upper_indptr),
                             shape=(self.n, self.n))
