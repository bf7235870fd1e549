"""A python-canopen LocalNode (an SDO server independent of this project) on a socketcand bus.

Usage: local_node.py --eds EDS --node-id N --socketcand HOST:PORT --seconds S

Serves SDO requests for S seconds; prints READY once it is on the bus, and at the end every value a
client wrote, as INDEX:SUB=HEX lines.
"""

import argparse
import sys
import time

import canopen


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--eds", required=True)
    ap.add_argument("--node-id", type=int, required=True)
    ap.add_argument("--socketcand", required=True)
    ap.add_argument("--seconds", type=float, required=True)
    args = ap.parse_args()
    host, port = args.socketcand.rsplit(":", 1)
    network = canopen.Network()
    network.connect(interface="socketcand", host=host, port=int(port), channel="can0")
    written = []

    def on_write(index, subindex, od, data):
        written.append((index, subindex, bytes(data)))

    node = canopen.LocalNode(args.node_id, args.eds)
    node.add_write_callback(on_write)
    network.add_node(node)
    print("READY", flush=True)
    time.sleep(args.seconds)
    network.disconnect()
    for index, sub, data in written:
        print(f"{index:04X}:{sub:02X}={data.hex().upper()}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
