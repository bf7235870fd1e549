#!/usr/bin/env python3
"""FoE with a real EtherCAT master (SOEM, through pysoem) against `ethercat-node`: files written and
read by pysoem's foe_write/foe_read, each file's bytes made from its name and size (`pattern`, the
same rule as the Rust test's), every byte read compared.

    pysoem_foe.py IFACE OP...

Each OP is `KIND:POS:NAME:SIZE[:boot]` (POS 1 = first slave), run in order with the chain in Pre-Op:

  - `w`    foe_write of SIZE bytes; it must return 1 (done);
  - `r`    foe_read of the file; it must be SIZE bytes, the pattern's;
  - `big`  foe_write of SIZE bytes that the slave refuses: SOEM returns -5 (EC_ERR_TYPE_FOE_ERROR,
           the slave's FoE Error frame; SOEM does not hand its code on: the emulator's log names it);
  - `none` foe_read of a file that is not there: SOEM returns no bytes (the emulator's log names
           its 0x8001);
  - `nofoe` foe_read from a slave without FoE: pysoem raises MailboxError with code 2 (the mailbox
           error reply "unsupported protocol");
  - `t`    foe_write of SIZE bytes, timed: one line `write SIZE bytes in S s: R bytes/s`.

With `:boot` the slave goes to Bootstrap first, as SOEM's firmware-update example does: the chain to
Init, the slave's mailbox moved to its bootstrap mailbox (0x1200 and 0x1300, 256 bytes each, from
examples/foe-device.esi.xml) with amend_mbx, the slave to Bootstrap (AL status 3), the op, then the
slave to Init, its standard mailbox (0x1000 and 0x1080, 128 bytes) back, and the chain to Pre-Op.

Every check compares exact values; the first mismatch ends the run with a message on stderr and
exit status 1. Exit status 2: the run could not start. On success one summary line on stdout.
"""

import sys
import time

INIT, PREOP, BOOT = 0x01, 0x02, 0x03
TIMEOUT_US = 2_000_000


class Fail(Exception):
    """A check that did not hold."""


def pattern(name, size):
    """The bytes of file `name` of `size` bytes: byte k is (7k + k // 251 + the sum of the name's
    bytes) mod 256."""
    seed = sum(name.encode())
    return bytes((7 * k + k // 251 + seed) % 256 for k in range(size))


def eq(actual, expected, what):
    if actual != expected:
        raise Fail(f"{what}: expected {expected!r}, got {actual!r}")


def to_state(m, state):
    m.state = state
    m.write_state()
    eq(m.state_check(state, 2_000_000), state, f"the chain in state {state}")


def boot(m, s):
    to_state(m, INIT)
    s.amend_mbx("out", 0x1200, 256)
    s.amend_mbx("in", 0x1300, 256)
    s.state = BOOT
    s.write_state()
    eq(s.state_check(BOOT, 2_000_000), BOOT, f"{s.name} in Bootstrap")


def unboot(m, s):
    s.state = INIT
    s.write_state()
    eq(s.state_check(INIT, 2_000_000), INIT, f"{s.name} back in Init")
    s.amend_mbx("out", 0x1000, 128)
    s.amend_mbx("in", 0x1080, 128)
    to_state(m, PREOP)


def run(m, op):
    kind, pos, name, size, *rest = op.split(":")
    s = m.slaves[int(pos) - 1]
    size = int(size)
    data = pattern(name, size)
    in_boot = rest == ["boot"]
    if in_boot:
        boot(m, s)
    line = None
    if kind == "w":
        eq(s.foe_write(name, 0, data, TIMEOUT_US), 1, f"foe_write {name}")
    elif kind == "t":
        t0 = time.monotonic()
        eq(s.foe_write(name, 0, data, TIMEOUT_US), 1, f"foe_write {name}")
        dt = time.monotonic() - t0
        line = f"write {size} bytes in {dt:.3f} s: {size / dt:.0f} bytes/s"
    elif kind == "r":
        eq(s.foe_read(name, 0, size + 1000, TIMEOUT_US), data, f"foe_read {name}")
    elif kind == "big":
        eq(s.foe_write(name, 0, data, TIMEOUT_US), -5, f"foe_write {name} refused")
    elif kind == "none":
        eq(s.foe_read(name, 0, 1000, TIMEOUT_US), b"", f"foe_read {name} not there")
    elif kind == "nofoe":
        import pysoem
        try:
            s.foe_read(name, 0, 1000, TIMEOUT_US)
            raise Fail(f"foe_read {name} from {s.name}: no error")
        except pysoem.MailboxError as e:
            eq(e.args[1], 2, f"foe_read {name} from {s.name}: mailbox error code")
    else:
        raise Fail(f"unknown op {op}")
    if in_boot:
        unboot(m, s)
    return line


def main():
    try:
        import pysoem
    except ImportError as e:
        print(f"pysoem is not importable: {e}", file=sys.stderr)
        return 2
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    m = pysoem.Master()
    m.open(sys.argv[1])
    try:
        if m.config_init() <= 0:
            raise Fail("config_init found no slave")
        to_state(m, PREOP)
        for op in sys.argv[2:]:
            line = run(m, op)
            if line:
                print(line)
        to_state(m, INIT)
    except Fail as e:
        print(f"FAIL: {e}", file=sys.stderr)
        return 1
    finally:
        m.close()
    print(f"{len(sys.argv) - 2} FoE operations done")
    return 0


if __name__ == "__main__":
    sys.exit(main())
