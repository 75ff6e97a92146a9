"""Compiled fixed-point formatter of :mod:`thermocal.io.csv_writer` (imports numba)."""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, nogil=True)
def format_rows(label_data, label_offsets, first_row, values, decimals, out):  # pragma: no cover
    """Write CSV rows ``label,value,value...\\n`` into ``out``; return the bytes used.

    Parameters
    ----------
    label_data : ndarray of uint8
        UTF-8 bytes of all row labels (an Arrow string array's data buffer).
    label_offsets : ndarray of int32
        Arrow offsets: the label of row ``r`` is ``label_data[offsets[r]:offsets[r + 1]]``.
    first_row : int
        Row of ``values[0]`` in the labels.
    values : ndarray of float64, shape (rows, columns)
        Finite values below 1e12 in magnitude, or NaN (written as an empty field).
    decimals : int
        Digits after the point; trailing zeros are dropped, negative zero is written ``0``.
    out : ndarray of uint8
        Buffer large enough for the text.
    """
    scale = 1
    for _ in range(decimals):
        scale *= 10
    digits = np.empty(24, dtype=np.uint8)
    pos = 0
    for i in range(values.shape[0]):
        for k in range(label_offsets[first_row + i], label_offsets[first_row + i + 1]):
            out[pos] = label_data[k]
            pos += 1
        for j in range(values.shape[1]):
            out[pos] = 44  # ","
            pos += 1
            x = values[i, j]
            if x != x:  # NaN: empty field
                continue
            q = np.int64(np.rint(x * scale))
            if q < 0:
                out[pos] = 45  # "-"
                pos += 1
                q = -q
            whole = q // scale
            frac = q - whole * scale
            n = 0
            while True:
                digits[n] = 48 + whole % 10
                whole //= 10
                n += 1
                if whole == 0:
                    break
            for k in range(n - 1, -1, -1):
                out[pos] = digits[k]
                pos += 1
            if frac > 0:
                width = decimals
                while frac % 10 == 0:
                    frac //= 10
                    width -= 1
                out[pos] = 46  # "."
                pos += 1
                for k in range(width - 1, -1, -1):
                    out[pos + k] = 48 + frac % 10
                    frac //= 10
                pos += width
        out[pos] = 10  # newline
        pos += 1
    return pos
