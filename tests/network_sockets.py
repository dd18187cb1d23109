"""The test process's own sockets (Linux /proc): what a test that must stay offline checks."""

import os
from pathlib import Path


def _sockets_of_this_process(protocol: str) -> list[tuple[str, int, str]]:
    """(local address hex, port, state hex) of this process's ``tcp`` or ``udp`` sockets (Linux
    /proc; IPv4 and IPv6)."""
    inodes = set()
    for fd in Path("/proc/self/fd").iterdir():
        try:
            target = os.readlink(fd)
        except OSError:
            continue
        if target.startswith("socket:["):
            inodes.add(target[8:-1])
    found = []
    for table in (f"/proc/self/net/{protocol}", f"/proc/self/net/{protocol}6"):
        for line in Path(table).read_text().splitlines()[1:]:
            fields = line.split()
            if fields[9] in inodes:
                address, port = fields[1].split(":")
                found.append((address, int(port, 16), fields[3]))
    return found


LOOPBACK_HEX = {"0100007F", "00000000000000000000000001000000"}  # 127.0.0.1 and ::1 in /proc


def network_exposure() -> list[str]:
    """UDP sockets (LCM multicast) and TCP listeners not bound to the loopback."""
    udp = [f"udp {a}:{p}" for a, p, _ in _sockets_of_this_process("udp")]
    listening = [f"tcp listen {a}:{p}" for a, p, state in _sockets_of_this_process("tcp")
                 if state == "0A" and a not in LOOPBACK_HEX]
    return udp + listening
