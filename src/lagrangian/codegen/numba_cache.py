"""numba's own cache of machine code: kept from ending a run when the disk is full, and
vouched for as soon as it is saved.

numba (``cache=True``) saves the machine code of each compiled function beside
its module on the first call; a full disk (or quota) made that an ``OSError``
out of the call, and the run died with exit 1 after the work was done.  Not
being able to save is not an error: the code runs, and is compiled again next
time.  :func:`tolerate_full_disk` (which every generated module calls) makes
numba's save say so with a :class:`~lagrangian.errors.CacheWarning` instead, and
after a save that worked lists the module's files at once
(:func:`~lagrangian.codegen.cache.vouch_for_numba_files`), so that other processes
use them while this one still runs.  Importing this module imports numba.
"""

from __future__ import annotations

import errno
import functools
import warnings

from numba.core import caching

from ..errors import CacheWarning
from .cache import vouch_for_numba_files

#: What a write that cannot go on for want of space says.
_NO_SPACE = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)


def tolerate_full_disk() -> None:
    """Wrap numba's ``Cache.save_overload`` (once per process) so that a full disk is a
    warning, any other error passes through, and a save that worked is vouched for."""
    save = caching.Cache.save_overload
    if getattr(save, "tolerates_full_disk", False):
        return

    @functools.wraps(save)
    def save_overload(self, sig, data):
        try:
            save(self, sig, data)
        except OSError as error:
            if error.errno not in _NO_SPACE:
                raise
            warnings.warn(
                CacheWarning(
                    f"numba could not keep its machine code on disk ({error.strerror}); "
                    "it is compiled again next time"
                ),
                stacklevel=2,
            )
            return
        source = getattr(getattr(self, "_py_func", None), "__code__", None)
        if source is not None:
            vouch_for_numba_files(source.co_filename)

    save_overload.tolerates_full_disk = True
    caching.Cache.save_overload = save_overload
