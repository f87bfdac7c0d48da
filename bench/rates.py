"""Rates with their counts and 95 % Wilson score intervals, shared by the bench scripts
(bench/classify/evaluate.py, bench/classify/realcal.py, bench/sensordir/tabulate.py).
A script in bench/<name>/ imports it after sys.path.insert(0, <its folder>/..)."""
import math


def wilson(k, n, z=1.96):
    """The Wilson score interval (lo, hi) of k successes in n trials; (nan, nan) when n is 0."""
    if n == 0:
        return (float("nan"), float("nan"))
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, c - h), min(1.0, c + h))


def rate(k, n):
    """'k/n = p% [lo, hi]' in percent with one decimal; 'k/0' when n is 0."""
    lo, hi = wilson(k, n)
    return f"{k}/{n} = {100 * k / n:.1f}% [{100 * lo:.1f}, {100 * hi:.1f}]" if n else f"{k}/0"
