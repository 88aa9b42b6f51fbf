#!/usr/bin/python3
"""Orbis's demo processing server: PyWPS 4.5 (Debian's python3-pywps) with terrain processes
written on GDAL's Python bindings (processes.py), served over WSGI by werkzeug on 127.0.0.1.

    /usr/bin/python3 tools/wps/serve.py --dem DEM.tif --dir WORKDIR [--port 0]

Prints "wps: http://127.0.0.1:PORT/wps" once it listens (port 0: a free one), then serves until
killed. WORKDIR holds PyWPS's configuration, its job database, work files and the outputs,
which are served under /outputs/ (the status documents of asynchronous jobs too).
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dem", required=True, help="the DEM the processes read (any GDAL raster)")
    parser.add_argument("--dir", required=True, help="a folder for configuration, jobs and outputs")
    parser.add_argument("--port", type=int, default=0, help="0: a free port")
    args = parser.parse_args()

    if not os.path.isfile(args.dem):
        sys.exit(f"wps: {args.dem}: no such file")
    work = os.path.abspath(args.dir)
    for sub in ("outputs", "work"):
        os.makedirs(os.path.join(work, sub), exist_ok=True)
    os.environ["ORBIS_WPS_DEM"] = os.path.abspath(args.dem)

    from werkzeug.serving import make_server
    from werkzeug.middleware.shared_data import SharedDataMiddleware

    # The port first (PyWPS's configuration names the addresses it gives out).
    server = make_server("127.0.0.1", args.port, lambda env, start: [], threaded=True)
    port = server.server_port
    base = f"http://127.0.0.1:{port}"
    config = os.path.join(work, "pywps.cfg")
    with open(config, "w") as f:
        f.write(f"""[metadata:main]
identification_title = Orbis demo processes
identification_abstract = Terrain analysis on a DEM: slope, aspect, hillshade, viewshed, profile, zonal statistics
provider_name = Orbis

[server]
url = {base}/wps
outputurl = {base}/outputs
outputpath = {work}/outputs
workdir = {work}/work
maxsingleinputsize = 20mb
maxrequestsize = 40mb
parallelprocesses = 4
maxprocesses = 8

[logging]
level = WARNING
file = {work}/pywps.log
database = sqlite:///{work}/pywps-jobs.sqlite3
""")

    from pywps import Service
    import processes

    service = Service(processes.all_processes(), [config])
    server.app = SharedDataMiddleware(service, {"/outputs": os.path.join(work, "outputs")})
    print(f"wps: {base}/wps", flush=True)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
