"""Python's cycle collector paused while a large structure is made.

Building a large model or deriving its equations keeps hundreds of thousands of SymPy
and SymEngine objects alive at once.  None of them form reference cycles (reference
counting frees them), but their number sets off the collector's full collections, each
walking the whole heap: 0.36 of 1.8 s of the 100-link chain's derivation.  Any cycle
made meanwhile is collected once the collector is back.
"""

from __future__ import annotations

import contextlib
import gc
from collections.abc import Iterator


@contextlib.contextmanager
def cycle_collector_paused() -> Iterator[None]:
    """The collector off inside the block, and left as it was found however the block
    ends (a result, an error, a deadline's ``OutOfTime``); a collector that was off stays
    off."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()
