#!/usr/bin/env python3
"""Development meshes for docs/decisions/classify.md §44: a truck mesh (binary PLY as roughen.py reads
it; the cab at +x, as share/vehicles/truck's models) with its body (x < x_max - CAB) stretched along x
so the whole is LENGTH m long; the cab, width and height kept, the bbox re-centred in x. Writes only
OUT.ply (development data: keep it out of the repository).

  bench/classify/stretch.py IN.ply OUT.ply LENGTH [CAB=3.0]"""
import os
import sys
ns = {}
src = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), 'roughen.py')).read().replace('\nmain()\n', '\n')
exec(compile(src, 'roughen', 'exec'), ns)
v, f = ns['read_ply'](sys.argv[1])
L = float(sys.argv[3]); cab = float(sys.argv[4]) if len(sys.argv) > 4 else 3.0
x0 = min(a[0] for a in v); x1 = max(a[0] for a in v)
xc = x1 - cab
s = (L - cab) / (xc - x0)
w = [((xc + (a[0] - xc) * s) if a[0] < xc else a[0], a[1], a[2]) for a in v]
m = 0.5 * (min(a[0] for a in w) + max(a[0] for a in w))
w = [(a[0] - m, a[1], a[2]) for a in w]
ns['write_ply'](sys.argv[2], w, f, 'stretched body x%.3f to %.2f m (classify.md 44, development)' % (s, L))
print(sys.argv[2], 'scale %.3f' % s, 'L %.2f' % (max(a[0] for a in w) - min(a[0] for a in w)))
