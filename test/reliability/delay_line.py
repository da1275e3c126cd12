#!/usr/bin/python3
"""A lossy, slow point-to-point IP link in user space ("netem without netem").

  delay_line.py --ns-a hapi_robot --ip-a 10.77.0.1 --ns-b hapi_server --ip-b 10.77.0.2 \
                --delay-ms 20 --loss 5 --stats stats.json [--seed 1]

Why: two_hosts.sh wants `tc qdisc ... netem delay 20ms loss 5%` on the link
between the robot and the server namespaces, but some kernels (e.g. small
VM kernels) are built without sch_netem ("Specified qdisc kind is unknown").
This script makes the same link itself: it opens two TUN devices in the
current namespace, moves one into each namespace (an open TUN stays attached
to its file descriptor when its interface changes namespace), gives them
point-to-point addresses, and relays every IP packet from one to the other
after a fixed delay, dropping each packet independently with probability
loss/100 in each direction (the netem model: i.i.d. loss, constant delay).

Outages: SIGUSR1 takes the link down (every packet dropped, both
directions, counted as packets_dropped_outage; as a radio out of range),
SIGUSR2 brings it back.

Runs until SIGINT/SIGTERM. Writes per-direction counters (packets and bytes
forwarded, packets dropped) to --stats as JSON every second and on exit.
Root only.
"""
import argparse
import fcntl
import heapq
import json
import os
import random
import select
import signal
import struct
import subprocess
import sys
import time

TUNSETIFF = 0x400454CA
IFF_TUN = 0x0001
IFF_NO_PI = 0x1000
MTU = 1500


def open_tun(name):
    fd = os.open("/dev/net/tun", os.O_RDWR | os.O_NONBLOCK)
    fcntl.ioctl(fd, TUNSETIFF, struct.pack("16sH", name.encode(), IFF_TUN | IFF_NO_PI))
    return fd


def sh(*cmd):
    subprocess.run(cmd, check=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ns-a", required=True)
    ap.add_argument("--ip-a", required=True)
    ap.add_argument("--ns-b", required=True)
    ap.add_argument("--ip-b", required=True)
    ap.add_argument("--dev-a", default="hapi-tun-a")
    ap.add_argument("--dev-b", default="hapi-tun-b")
    ap.add_argument("--delay-ms", type=float, default=20.0, help="one-way delay [ms], each direction")
    ap.add_argument("--loss", type=float, default=5.0, help="packet loss [%%], each direction, i.i.d.")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--stats", required=True, help="JSON file written on exit")
    ap.add_argument("--ready", help="file created once the link is up")
    args = ap.parse_args()
    if not (0.0 <= args.loss < 100.0) or args.delay_ms < 0.0:
        ap.error("need 0 <= loss < 100 and delay >= 0")

    fd_a, fd_b = open_tun(args.dev_a), open_tun(args.dev_b)
    for dev, ns, ip, peer in ((args.dev_a, args.ns_a, args.ip_a, args.ip_b),
                              (args.dev_b, args.ns_b, args.ip_b, args.ip_a)):
        sh("ip", "link", "set", dev, "netns", ns)
        sh("ip", "-n", ns, "addr", "add", ip, "peer", peer, "dev", dev)
        sh("ip", "-n", ns, "link", "set", dev, "mtu", str(MTU), "up")
    if args.ready:
        open(args.ready, "w").close()

    rng = random.Random(args.seed)
    delay = args.delay_ms / 1000.0
    p_loss = args.loss / 100.0
    other = {fd_a: fd_b, fd_b: fd_a}
    name = {fd_a: "%s->%s" % (args.ns_a, args.ns_b), fd_b: "%s->%s" % (args.ns_b, args.ns_a)}
    stats = {n: {"packets_in": 0, "packets_dropped": 0, "packets_dropped_outage": 0, "packets_out": 0,
                 "bytes_out": 0, "write_errors": 0}
             for n in name.values()}
    down = []  # non-empty while the link is out
    signal.signal(signal.SIGUSR1, lambda *_: down.append(1))
    signal.signal(signal.SIGUSR2, lambda *_: down.clear())
    queue = []  # (due time, sequence, destination fd, packet, direction)
    seq = 0
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    poller = select.poll()
    poller.register(fd_a, select.POLLIN)
    poller.register(fd_b, select.POLLIN)
    next_dump = time.monotonic() + 1.0
    while not stop:
        now = time.monotonic()
        if now >= next_dump:
            # Counters while running: the caller reads them with the link
            # still up (its nodes need the link to shut down cleanly).
            write_stats(args, stats)
            next_dump = now + 1.0
        while queue and queue[0][0] <= now:
            _, _, dst, pkt, d = heapq.heappop(queue)
            try:
                os.write(dst, pkt)
                stats[d]["packets_out"] += 1
                stats[d]["bytes_out"] += len(pkt)
            except OSError:
                # The kernel refused the packet (queue full): a loss too, counted apart.
                stats[d]["write_errors"] += 1
        timeout_ms = 50 if not queue else max(0, int((queue[0][0] - now) * 1000.0))
        try:
            events = poller.poll(timeout_ms)
        except InterruptedError:
            continue
        for fd, _ in events:
            while True:
                try:
                    pkt = os.read(fd, 65536)
                except BlockingIOError:
                    break
                except OSError:
                    break
                d = name[fd]
                stats[d]["packets_in"] += 1
                if down:
                    stats[d]["packets_dropped_outage"] += 1
                    continue
                if rng.random() < p_loss:
                    stats[d]["packets_dropped"] += 1
                    continue
                seq += 1
                heapq.heappush(queue, (time.monotonic() + delay, seq, other[fd], pkt, d))
    write_stats(args, stats)
    return 0


def write_stats(args, stats):
    for s in stats.values():
        s["loss_measured_pct"] = 100.0 * s["packets_dropped"] / s["packets_in"] if s["packets_in"] else 0.0
    tmp = args.stats + ".tmp"
    with open(tmp, "w") as f:
        json.dump({"delay_ms": args.delay_ms, "loss_pct": args.loss, "directions": stats}, f, indent=1)
    os.replace(tmp, args.stats)  # readers never see a half-written file


if __name__ == "__main__":
    sys.exit(main())
