"""Brings the live view of a demo that runs in a private network namespace to this machine's
loopback: the page and the Foxglove feed listen on 127.0.0.1 inside the namespace, which a
browser outside cannot reach. Two halves meet at Unix sockets in a directory (a path on the
file system, which both sides see):

  outside (on the host):      127.0.0.1:PORT  ->  DIR/PORT.sock
  inside (in the namespace):  DIR/PORT.sock   ->  127.0.0.1:PORT

  python3 tests/peer/web_bridge.py outside|inside --dir DIR --ports 8080,8765

Only TCP byte streams are carried (HTTP and WebSocket); no DDS traffic passes here.
"""

import argparse
import asyncio
import os
import sys


async def pipe(reader, writer):
    try:
        while data := await reader.read(65536):
            writer.write(data)
            await writer.drain()
    except (ConnectionError, asyncio.CancelledError):
        pass
    finally:
        writer.close()


async def splice(client_r, client_w, open_target):
    try:
        target_r, target_w = await open_target()
    except OSError:
        client_w.close()
        return
    await asyncio.gather(pipe(client_r, target_w), pipe(target_r, client_w))


async def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("side", choices=["outside", "inside"])
    ap.add_argument("--dir", required=True)
    ap.add_argument("--ports", required=True)
    args = ap.parse_args()
    servers = []
    for port in [int(p) for p in args.ports.split(",") if p]:
        sock = os.path.join(args.dir, f"{port}.sock")
        if args.side == "outside":
            target = lambda s=sock: asyncio.open_unix_connection(s)
            try:
                servers.append(await asyncio.start_server(
                    lambda r, w, t=target: splice(r, w, t), "127.0.0.1", port))
            except OSError as e:
                print(f"web bridge: port {port} on this machine is taken ({e.strerror}); "
                      "that address shows another program", file=sys.stderr, flush=True)
        else:
            target = lambda p=port: asyncio.open_connection("127.0.0.1", p)
            if os.path.exists(sock):
                os.unlink(sock)
            servers.append(await asyncio.start_unix_server(
                lambda r, w, t=target: splice(r, w, t), sock))
    await asyncio.gather(*(s.serve_forever() for s in servers))


if __name__ == "__main__":
    try:
        asyncio.run(main())
    except KeyboardInterrupt:
        pass
