"""A fixed sparsity pattern: scatter batches of element matrices into a CSR matrix fast.

Element contributions come as groups: a group is a dof array `dofs` of shape (n_local, n_items)
(global dof numbers, or -1 for an entry to drop, such as a Dirichlet dof); its element matrices
come as an array (n_items, n_local, n_local). The pattern is built
once with `np.unique` over the linear keys row * n + col; each assembly is then a single
`np.bincount` of the element values into CSR data order. Rows/columns are the free dofs only:
Dirichlet dofs are condensed out by the caller's `free_index` map (global dof -> free number, -1).
The pattern also knows its transpose permutation (a symmetry check costs one gather) and its upper
triangle (the input of symmetric solvers).
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp


class Pattern:
    def __init__(self, free_index: np.ndarray, groups: list[np.ndarray]):
        self.n = int(free_index.max()) + 1
        keys = []
        for dofs in groups:
            f = free_index[dofs].T                     # (n_items, n_local)
            n_items, n_local = f.shape
            rows = np.broadcast_to(f[:, :, None], (n_items, n_local, n_local)).reshape(-1)
            cols = np.broadcast_to(f[:, None, :], (n_items, n_local, n_local)).reshape(-1)
            # entries in a Dirichlet row or column get key -1: they go to a discard bin
            key = np.where((rows >= 0) & (cols >= 0), rows.astype(np.int64) * self.n + cols, -1)
            keys.append(key)
        all_keys = np.concatenate(keys)
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
        # structurally symmetric: element blocks are square in the same dofs).
        self._transpose = np.searchsorted(unique, col * self.n + row)
        upper = col >= row
        self._upper = np.flatnonzero(upper)
        self._upper_indices = self.indices[upper]
        self._upper_indptr = np.searchsorted(row[upper], np.arange(self.n + 1)).astype(np.int32)

    def assemble(self, blocks: list[np.ndarray]) -> sp.csr_matrix:
        """`blocks[g]` has shape (n_items, n_local, n_local) for group g (items first, so element
        matrices are written in place without a transposed copy)."""
        values = np.concatenate([b.reshape(-1) for b in blocks])
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
