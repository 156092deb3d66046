"""Serves the browser twin (the folder scripts/build_web.sh builds) on 127.0.0.1.

`rosrun kane_sim web [--port P]` prints the page's URL and serves until Ctrl-C. Only the
loopback address is bound: the page runs everything in the visitor's browser, and a simulator's
developer server has no business on other interfaces.
"""
import functools
import http.server
import os
import socketserver

MIME_TYPES = {".wasm": "application/wasm", ".js": "text/javascript", ".mjs": "text/javascript",
              ".yaml": "text/yaml", ".css": "text/css", ".html": "text/html"}
NEEDED = ("index.html", "kane_sim.js", "kane_sim.wasm", "mechanism.yaml")


class WebDirError(Exception):
    """The page's folder is missing or incomplete: the message says how to build it."""


def _candidates(script_path):
    if os.environ.get("KANE_SIM_WEB_DIR"):
        yield os.environ["KANE_SIM_WEB_DIR"]
    for prefix in filter(None, os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep)):
        yield os.path.join(prefix, "share", "kane_sim", "web")  # an install space
        if os.path.basename(os.path.normpath(prefix)) == "devel":
            yield os.path.join(os.path.dirname(os.path.normpath(prefix)), "web")  # a build folder
    if os.environ.get("KANE_SIM_BUILD_DIR"):
        yield os.path.join(os.environ["KANE_SIM_BUILD_DIR"], "web")
    # The checkout's own build folder (scripts/build_dir.sh): build-<checkout> beside it.
    checkout = os.path.dirname(os.path.dirname(os.path.realpath(script_path)))
    yield os.path.join(os.path.dirname(checkout), "build-" + os.path.basename(checkout), "web")


def find_web_dir(given=None, script_path=__file__):
    """The folder to serve: `given`, else the first built one of the usual places."""
    places = [given] if given is not None else list(_candidates(script_path))
    for place in places:
        if all(os.path.isfile(os.path.join(place, name)) for name in NEEDED):
            return os.path.abspath(place)
    if given is not None:
        missing = [n for n in NEEDED if not os.path.isfile(os.path.join(given, n))]
        raise WebDirError("--dir %s is not a built page (missing %s): bash scripts/build_web.sh "
                          "builds one once the page's toolchain is installed (bash "
                          "scripts/install_deps.sh --web)" % (given, ", ".join(missing)))
    raise WebDirError("no built page found (looked in %s): install the page's toolchain, "
                      "emscripten and npm (bash scripts/install_deps.sh --web, about 1 GB), and "
                      "build the page (bash scripts/build_web.sh)"
                      % ", ".join(dict.fromkeys(places)))


class _Handler(http.server.SimpleHTTPRequestHandler):
    extensions_map = dict(http.server.SimpleHTTPRequestHandler.extensions_map, **MIME_TYPES)

    def end_headers(self):
        # A rebuilt module is served at once, never an older copy from the browser's cache.
        self.send_header("Cache-Control", "no-store")
        super().end_headers()

    def log_message(self, format, *args):  # noqa: A002 (the base class's name)
        pass  # quiet: a page load is a dozen requests


class _Server(socketserver.ThreadingMixIn, http.server.HTTPServer):
    daemon_threads = True
    allow_reuse_address = True


def make_server(web_dir, port):
    """The server on 127.0.0.1:port (0: a free port); OSError when the port is taken."""
    if not 0 <= port <= 65535:
        raise ValueError("--port must be in [0, 65535], got %d" % port)
    handler = functools.partial(_Handler, directory=web_dir)
    return _Server(("127.0.0.1", port), handler)
