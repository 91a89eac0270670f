"""A PNG's bytes without its text chunks. svetlo's still images carry their provenance (the
render's seconds, the request: docs/provenance.md) in an iTXt chunk, so two answers hold the
same image when these bytes are equal, whatever their provenance says."""
import struct

SIGNATURE = b"\x89PNG\r\n\x1a\n"


def without_text(data):
    """`data` less its tEXt, zTXt and iTXt chunks when it is a PNG; anything else as it is."""
    if data[:8] != SIGNATURE:
        return data
    out, at = [SIGNATURE], 8
    while at + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        end = at + 12 + length
        if kind not in (b"tEXt", b"zTXt", b"iTXt"):
            out.append(data[at:end])
        at = end
    return b"".join(out)
