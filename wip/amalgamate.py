#!/usr/bin/env python3
"""Development only: splice wip/<module>_{api,impl}.h into cloth.h in place of their #include
blocks, for the modules named on the command line. The fragments are then deleted."""
import re, sys, os
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
path = os.path.join(root, 'cloth.h')
s = open(path).read()
for m in sys.argv[1:]:
    for half in ('api', 'impl'):
        frag = os.path.join(root, 'wip', '%s_%s.h' % (m, half))
        text = open(frag).read().rstrip('\n') + '\n'
        guarded = '#if !defined(CLOTH_WIP_ONLY) || defined(CLOTH_WIP_%s)\n#include "wip/%s_%s.h"\n#endif\n' % (m.upper(), m, half)
        plain = '#include "wip/%s_%s.h"\n' % (m, half)
        if guarded in s:
            s = s.replace(guarded, text + '\n')
        elif plain in s:
            s = s.replace(plain, text + '\n')
        else:
            sys.exit('no include block for %s_%s' % (m, half))
        os.remove(frag)
open(path, 'w').write(s)
