"""The memory a computation may take: what the machine has available now, and the refusal of a request whose
arrays would not fit in it (before any work)."""

from __future__ import annotations

import os


def available_memory() -> int | None:
    """Bytes of memory available to a new computation (MemAvailable of /proc/meminfo, else the free physical
    pages); None where the system does not say."""
    try:
        with open("/proc/meminfo", encoding="ascii") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, OSError, ValueError):
        return None


def size(n: float) -> str:
    """``n`` bytes in binary units, three significant digits: ``"1.5 GiB"``."""
    units = ("B", "KiB", "MiB", "GiB", "TiB", "PiB")
    k = 0
    while n >= 1024 and k < len(units) - 1:
        n, k = n / 1024, k + 1
    return f"{n:.3g} {units[k]}"


__all__ = ["available_memory", "size"]
