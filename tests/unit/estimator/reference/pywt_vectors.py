# SPDX-License-Identifier: MIT
# Independent reference for p4_dwt_test.cpp: PyWavelets' filters, pywt.dwt and pywt.idwt.
# Usage: pywt_vectors.py INPUT OUTPUT  (run by the test with Debian's /usr/bin/python3, which
# has python3-pywt; the `python3` of a pyenv shim may not).
# INPUT lines:  signal NAME v1 v2 ...        a block for pywt.dwt
#               bands NAME M a1..aM d1..dM   approximation and detail for pywt.idwt
# OUTPUT lines: filter WAVELET dec_lo|dec_hi|rec_lo|rec_hi v...
#               dwt WAVELET MODE NAME cA|cD v...
#               idwt WAVELET MODE NAME v...
# Values are written with repr(), which reads back as the same double.
import sys

WAVELETS = ("haar", "db4", "sym4")
MODES = ("periodization", "symmetric")


def main(argv):
    if len(argv) != 3:
        sys.stderr.write("usage: pywt_vectors.py INPUT OUTPUT\n")
        return 2
    try:
        import pywt
    except ImportError as e:
        sys.stderr.write("pywt_vectors.py: PyWavelets is not importable by %s (%s): run "
                         "scripts/setup, which installs Debian's python3-pywt\n"
                         % (sys.executable, e))
        return 3
    signals, bands = [], []
    with open(argv[1]) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "signal":
                signals.append((t[1], [float(v) for v in t[2:]]))
            elif t[0] == "bands":
                m = int(t[2])
                vals = [float(v) for v in t[3:]]
                bands.append((t[1], vals[:m], vals[m:2 * m]))
            else:
                sys.stderr.write("pywt_vectors.py: unknown input line %r\n" % t[0])
                return 2

    def row(*head_and_values):
        *head, values = head_and_values
        return " ".join(list(head) + [repr(float(v)) for v in values]) + "\n"

    out = []
    for w in WAVELETS:
        wav = pywt.Wavelet(w)
        for kind in ("dec_lo", "dec_hi", "rec_lo", "rec_hi"):
            out.append(row("filter", w, kind, getattr(wav, kind)))
        for mode in MODES:
            for name, x in signals:
                cA, cD = pywt.dwt(x, w, mode=mode)
                out.append(row("dwt", w, mode, name, "cA", cA))
                out.append(row("dwt", w, mode, name, "cD", cD))
            for name, a, d in bands:
                if mode == "symmetric" and 2 * len(a) - wav.rec_len + 2 < 1:
                    continue  # too short for pywt too
                out.append(row("idwt", w, mode, name, pywt.idwt(a, d, w, mode=mode)))
    with open(argv[2], "w") as f:
        f.writelines(out)
    sys.stdout.write("pywt %s: %d lines\n" % (pywt.__version__, len(out)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
