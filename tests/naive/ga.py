"""Oracles of the GA's numba kernels (:mod:`growsim.kernels.ga`): slow NumPy / Python.

Each function is named after the kernel it mirrors; it returns new arrays where the kernel
writes into output arguments.
"""

from __future__ import annotations

import numpy as np

from growsim.kernels import ga as K


def decode_bits(bits, offset, nbits, code, low, high, k, weights):
    """Per element, straight from the formulas in the Bits docstring."""
    n, p = bits.shape[0], offset.shape[0]
    out = np.empty((n, p))
    for i in range(n):
        for j in range(p):
            b = [int(x) for x in bits[i, offset[j] : offset[j] + nbits[j]]]
            nb = nbits[j]
            if code[j] == K.CODE_WEIGHTED:
                w = weights[offset[j] : offset[j] + nb]
                out[i, j] = low[j] + sum(wi * bi for wi, bi in zip(w, b)) / w.sum() * (
                    high[j] - low[j]
                )
                continue
            if code[j] == K.CODE_GRAY:
                # binary bit t = XOR of Gray bits 0..t
                b = [int(np.bitwise_xor.reduce(b[: t + 1])) for t in range(nb)]
            v = int("".join(map(str, b)), 2)
            if code[j] == K.CODE_FRACTION:
                out[i, j] = low[j] + v / 2**nb * (high[j] - low[j])
            elif code[j] == K.CODE_INDEX:
                out[i, j] = low[j] + (v * k[j]) // 2**nb
            else:
                out[i, j] = low[j] + v / (2**nb - 1) * (high[j] - low[j])
    return out


#: the kernels' coding numbers by the names a :class:`~growsim.ga.Bits` field takes
CODES = {
    "binary": K.CODE_BINARY,
    "gray": K.CODE_GRAY,
    "weighted": K.CODE_WEIGHTED,
    "fraction": K.CODE_FRACTION,
}


def layout(fields):
    """A bit genome's layout from its fields' public description alone, by the rules the
    :class:`~growsim.ga.Genome` docs state (never its private arrays): the arguments of
    :func:`decode_bits` after ``bits``. Fields follow one another, a field's ``size``
    elements one after the other; a :class:`~growsim.ga.Bits` element takes ``bits`` bits,
    an ``Integer`` ``low..high`` or a ``Categorical`` of ``k`` choices the fewest bits that
    count ``k`` values (at least one), decoded as ``low + (v * k) // 2**nbits``."""
    from growsim.ga import Bits, Categorical, Integer

    offset, nbits, code, low, high, k, weights = [], [], [], [], [], [], []
    pos = 0
    for f in fields:
        for _ in range(f.size):
            if isinstance(f, Bits):
                nb = f.bits
                c = CODES[f.coding]
                lo, hi, kv = f.low, f.high, 0
                w = list(f.weights) if f.coding == "weighted" else [0.0] * nb
            else:
                assert isinstance(f, (Integer, Categorical)), f
                kv = f.high - f.low + 1 if isinstance(f, Integer) else len(f.choices)
                lo = f.low if isinstance(f, Integer) else 0
                nb = 1
                while 2**nb < kv:
                    nb += 1
                c, hi, w = K.CODE_INDEX, lo + kv - 1, [0.0] * nb
            offset.append(pos)
            nbits.append(nb)
            code.append(c)
            low.append(float(lo))
            high.append(float(hi))
            k.append(kv)
            weights += w
            pos += nb
    ints = [np.array(a, dtype=np.int64) for a in (offset, nbits, code)]
    return (*ints, np.array(low), np.array(high), np.array(k, dtype=np.int64), np.array(weights))


def cut_crossover(a, b, ptr, cuts):
    """Walk each pair's genome, toggling the source parent at every cut."""
    m, L = a.shape
    c1, c2 = a.copy(), b.copy()
    for i in range(m):
        mine = list(cuts[ptr[i] : ptr[i + 1]])
        swapped = False
        for t in range(L):
            swapped ^= mine.count(t) % 2 == 1
            if swapped:
                c1[i, t], c2[i, t] = b[i, t], a[i, t]
    return c1, c2


def word_crossover(a, b, words):
    """Swap gene t where bit t % 64 of word t // 64 is set."""
    m, L = a.shape
    c1, c2 = a.copy(), b.copy()
    for i in range(m):
        for t in range(L):
            if (int(words[i, t // 64]) >> (t % 64)) & 1:
                c1[i, t], c2[i, t] = b[i, t], a[i, t]
    return c1, c2


def ones_per_locus(bits):
    """Column sums."""
    return bits.astype(np.int64).sum(axis=0)


def sbx(a, b, low, high, top, eta, gene_rate, r_act, r_u, r_flip):
    """Vectorised bounded SBX (Deb and Agrawal) with the same uniforms as the kernel."""
    y1, y2 = np.minimum(a, b), np.maximum(a, b)
    d = y2 - y1
    act = (r_act < gene_rate) & (d > 1e-14)
    dd = np.where(act, d, 1.0)

    def betaq(beta):
        alpha = 2.0 - beta ** (-(eta + 1.0))
        with np.errstate(all="ignore"):
            lo = (r_u * alpha) ** (1.0 / (eta + 1.0))
            hi = (1.0 / (2.0 - r_u * alpha)) ** (1.0 / (eta + 1.0))
        return np.where(r_u <= 1.0 / alpha, lo, hi)

    with np.errstate(all="ignore"):
        k1 = 0.5 * (y1 + y2 - betaq(1.0 + 2.0 * (y1 - low) / dd) * d)
        k2 = 0.5 * (y1 + y2 + betaq(1.0 + 2.0 * (high - y2) / dd) * d)
    k1 = np.clip(k1, low, top)
    k2 = np.clip(k2, low, top)
    flip = r_flip < 0.5
    c1 = np.where(act, np.where(flip, k2, k1), a)
    c2 = np.where(act, np.where(flip, k1, k2), b)
    return c1, c2


def byte_word_crossover(a, b, words):
    """The uint8 kernel's contract is :func:`word_crossover`'s: the same swaps."""
    return word_crossover(a, b, words)


def byte_word_crossover_pairs(pop, ia, ib, words, n):
    """Gather the pairs, cross them as :func:`word_crossover`, first children then second
    children, the first ``n`` rows."""
    c1, c2 = word_crossover(pop[ia], pop[ib], words)
    return np.concatenate([c1, c2])[:n]


def self_adaptive_mutation(
    x, low, high, top, strategy, tau, min_sigma, max_sigma, poly_rate, poly_eta, gauss_rate,
    r_hit, r_u, z_tau, z, r_gauss,
):  # fmt: skip
    """Vectorised: the polynomial step on the hit genes, then the Gaussian step."""
    p = x.shape[1]
    span = high - low
    e = poly_eta + 1.0
    with np.errstate(all="ignore"):
        b1 = 2.0 * r_u + (1.0 - 2.0 * r_u) * (1.0 - (x - low) / span) ** e
        b2 = 2.0 * (1.0 - r_u) + 2.0 * (r_u - 0.5) * (1.0 - (high - x) / span) ** e
        dq = np.where(r_u < 0.5, b1 ** (1.0 / e) - 1.0, 1.0 - b2 ** (1.0 / e))
    y = np.where(r_hit < poly_rate, np.clip(x + dq * span, low, top), x)
    s = np.clip(strategy * np.exp(tau * z_tau), min_sigma, max_sigma)
    y = np.where(r_gauss < gauss_rate, y + z * s[:, None] * span / np.sqrt(p), y)
    return np.clip(y, low, top), s


def portfolio_mutation(
    x, low, high, top, strategy, tau, min_sigma, max_sigma, poly_rate, poly_eta,
    r_hit, r_u, z_tau, z, r_axis, flip,
):  # fmt: skip
    """Per child, in Python: switch the move and crossover, then the polynomial and
    Gaussian steps of :func:`self_adaptive_mutation` with the move's genes and lengths."""
    m, p = x.shape
    out_x = np.empty((m, p))
    out_s = np.array(strategy, dtype=np.float64)  # columns past the third are copied
    for i in range(m):
        move = 1.0 - strategy[i, 1] if flip[0, i] else strategy[i, 1]
        cross = 1.0 - strategy[i, 2] if flip[1, i] else strategy[i, 2]
        iso = move == 1.0
        hits = np.ones(p) * 0.0 if iso else np.where(r_axis[i] < 1.0 / p, 0.0, 1.0)
        zi = z[i] if iso else z[i] * np.sqrt(p)
        y, s = self_adaptive_mutation(
            x[i : i + 1], low, high, top, strategy[i : i + 1, 0], tau, min_sigma, max_sigma,
            poly_rate, poly_eta, 0.5, r_hit[i : i + 1], r_u[i : i + 1], z_tau[i : i + 1],
            zi[None, :], hits[None, :],
        )  # fmt: skip
        out_x[i] = y[0]
        out_s[i, :3] = (s[0], move, cross)
    return out_x, out_s


def differential_trials(pop, base, target, r1, r2, u, forced, f, cr, low, top):
    """Vectorised: the donors, the genes taken from them, clipped (``f``, ``cr``: scalars
    or one per trial)."""
    f = np.broadcast_to(np.asarray(f, np.float64), base.shape)[:, None]
    cr = np.broadcast_to(np.asarray(cr, np.float64), base.shape)[:, None]
    donor = pop[base] + f * (pop[r1] - pop[r2])
    take = u < cr
    take[np.arange(len(base)), forced] = True
    return np.clip(np.where(take, donor, pop[target]), low, top)
