"""What `rosrun kane_sim sweep` does (scripts/sweep is its door: arguments, signals, exit codes):
simulate's sweeps on this machine or on a Dask cluster, writing the same CSV as `simulate
--sweep`, rows in case order. Importable and unit-tested (test/python/test_sweep_tool.py)."""
import math
import re
import signal
import sys
import time

# sweep's own flags (the cluster's); every other flag is simulate's, parsed by simulate's own
# parser (kane_sim._core.simulate_options) so both take one grammar and give one message.
OWN = {"--scheduler": None, "--chunk": None, "--connect-timeout": None}


class UsageError(Exception):
    pass


class Stop(BaseException):
    """SIGTERM (or SIGHUP): stop as Ctrl-C does, exit 128 + the signal. A BaseException, as
    KeyboardInterrupt is, so that no `except Exception` on the way (the scheduler's connection)
    takes it for a failure."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def stopped_before_start(e):
    """Ctrl-C or SIGTERM/SIGHUP before any case ran: said, exit 128 + the signal."""
    print("sweep: stopped before it started", file=sys.stderr)
    return 128 + (e.signum if isinstance(e, Stop) else signal.SIGINT)


def on_stop_signal(signum, frame):
    raise Stop(signum)


class Progress:
    """A progress line on stderr while a cluster's chunks come back, only on a terminal (as
    simulate's): "sweep: 40.0 % (400 of 1000 cases)", rewritten at most four times a second and
    erased at the end."""

    def __init__(self, total, stream=None):
        self.stream = stream or sys.stderr
        self.total, self.shown, self.last = total, self.stream.isatty() and total > 0, None

    def update(self, done):
        now = time.monotonic()
        if not self.shown or (self.last is not None and now - self.last < 0.25):
            return
        self.last = now
        self.stream.write("\r\033[Ksweep: %.1f %% (%d of %d cases)" % (
            100.0 * done / self.total, done, self.total))
        self.stream.flush()

    def finish(self):
        if self.shown and self.last is not None:
            self.stream.write("\r\033[K")
            self.stream.flush()
        self.shown = False


class Rows:
    """The CSV through simulate's own writer (FILE.partial until finish(); a device, a pipe or a
    link written in place; stdout without a file): the header, then each chunk's rows in case
    order as soon as those before it are written."""

    def __init__(self, path, header):
        from kane_sim import _core
        self.name = path or "stdout"
        self.out = _core.CsvOutput(path)
        self.pending, self.next = {}, 0
        self.out.write(header)

    def add(self, index, text):
        self.pending[index] = text
        while self.next in self.pending:
            self.out.write(self.pending.pop(self.next))
            self.next += 1

    def flush_rest(self):
        """After a stop: the finished chunks still waiting for an unfinished one, in order."""
        for index in sorted(self.pending):
            self.out.write(self.pending.pop(index))

    def finish(self):
        self.out.finish()


def _split(argv):
    """(sweep's own flags as a dict, the rest for simulate's parser). --flag VALUE or
    --flag=VALUE, each at most once."""
    own, rest, i = {}, [], 0
    while i < len(argv):
        flag, _, value = argv[i].partition("=")
        if flag in OWN:
            if flag in own:
                raise UsageError("%s given more than once" % flag)
            if not _:
                if i + 1 >= len(argv):
                    raise UsageError("%s needs a value" % flag)
                i += 1
                value = argv[i]
                if value.startswith("--"):
                    raise UsageError("%s needs a value, got the flag %s" % (flag, value))
            own[flag] = value
        else:
            rest.append(argv[i])
        i += 1
    return own, rest


def _whole(flag, text, low, high):
    value = int(text) if re.fullmatch(r"[+-]?[0-9]+", text) else None  # ASCII digits only
    if value is None:
        raise UsageError("%s takes a whole number, got %r" % (flag, text))
    if not low <= value <= high:
        raise UsageError("%s must be in [%d, %d], got %r" % (flag, low, high, text))
    return value


def _seconds(flag, text, high):
    if not re.fullmatch(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?", text):
        raise UsageError("%s takes a number, got %r" % (flag, text))
    value = float(text)
    if not (math.isfinite(value) and 0 < value <= high):
        raise UsageError("%s must be in (0, %g] s, got %r" % (flag, high, text))
    return value


def arguments(argv):
    """The sweep's settings: simulate's options (a sweep required, no bag or replay) and the
    cluster's."""
    from kane_sim import _core
    own, rest = _split(argv)
    try:
        options = _core.simulate_options(rest)
    except ValueError as e:
        raise UsageError(str(e))
    if not options["sweep"]:
        raise UsageError("give --sweep KEY=START:STOP:COUNT (repeatable) or --sweep-file FILE")
    options["scheduler"] = own.get("--scheduler")
    if options["scheduler"] is not None and not options["scheduler"].strip():
        raise UsageError("--scheduler needs tcp://HOST:PORT or a scheduler file, got ''")
    options["chunk"] = _whole("--chunk", own.get("--chunk", "64"), 1, 100000)
    options["connect_timeout"] = _seconds("--connect-timeout",
                                          own.get("--connect-timeout", "10"), 3600)
    for flag in ("--chunk", "--connect-timeout"):
        if flag in own and options["scheduler"] is None:
            raise UsageError("%s is for --scheduler (the cluster's tasks)" % flag)
    if options["scheduler"] and options["jobs"]:
        raise UsageError("--jobs is this machine's threads; with --scheduler the cluster's "
                         "workers decide (start them with --nthreads)")
    return options


def _silence_dask_logs():
    """Dask logs its connection troubles with tracebacks: this tool says what happened."""
    import logging
    try:
        import distributed  # noqa: F401  (its loggers exist from here on)
    except ImportError:
        pass  # cluster.connect says what to install
    for name in list(logging.root.manager.loggerDict):
        if name.split(".")[0] in ("distributed", "tornado", "asyncio"):
            logging.getLogger(name).setLevel(logging.CRITICAL + 1)


def run(args):
    """The sweep of `args` (arguments()): the CSV written, a summary on stderr; the exit code."""
    import kane_sim
    from kane_sim import _core, cluster
    if args["default_config"]:
        print("no --config given: using the package's default %s" % args["config"],
              file=sys.stderr)
    try:
        cfg = kane_sim.Config(args["config"])
        if args["integrator"]:
            cfg = cfg.with_values({"simulation.integrator": args["integrator"]})
    except kane_sim.ConfigError as e:  # as simulate words it: the file, then the loader's words
        print("sweep: error: %s%s" % (args["config"] + ": " if args["config"] else "", e),
              file=sys.stderr)
        return 1
    keys, rows, profile = args["sweep_keys"], args["sweep_cases"], args["torque"]
    try:
        # What simulate refuses before it runs (keys, duration, jobs, simd), refused here first.
        _core.sweep(cfg._core, list(keys), [], args["duration"], profile, args["jobs"],
                    args["simd"], args["vector_trig"])
        if args["scheduler"]:
            _silence_dask_logs()
        client = cluster.connect(args["scheduler"], args["connect_timeout"]) if args["scheduler"] else None
    except ValueError as e:
        message = str(e)
        print(message if message.startswith("sweep: ") else "sweep: " + message, file=sys.stderr)
        return 2
    except (KeyboardInterrupt, Stop) as e:
        return stopped_before_start(e)
    try:
        rows_out = Rows(args["csv"], _core.sweep_csv_header(list(keys)))
    except BrokenPipeError:
        raise
    except OSError as e:
        print("sweep: %s" % (e.strerror or e), file=sys.stderr)
        return 4
    start = time.monotonic()
    chunk = args["chunk"] if client else max(len(rows), 1)
    statuses = []

    progress = Progress(len(rows)) if client else None

    def take(index, result):
        rows_out.add(index, result["csv_rows"])
        statuses.extend((index * chunk + i, s, e) for i, (s, e) in
                        enumerate(zip(result["status"], result["error"])))
        if progress:
            progress.update(len(statuses))
    try:
        if client:
            try:
                cluster.run(client, cfg.yaml(), list(keys), rows, args["duration"], profile,
                            args["simd"], args["vector_trig"], chunk, on_chunk=take)
            finally:
                try:
                    client.close(timeout=5)
                except Exception:  # a lost scheduler: nothing left to close
                    pass
        else:
            take(0, _core.sweep(cfg._core, list(keys), rows, args["duration"], profile, args["jobs"],
                                args["simd"], args["vector_trig"], 0))
    except (KeyboardInterrupt, Stop, cluster.Failed) as e:
        if progress:
            progress.finish()
        for stop in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
            signal.signal(stop, signal.SIG_IGN)  # a second Ctrl-C must not lose the rows
        partial = getattr(e, "result", None)  # a local sweep's finished cases
        if partial is not None and "csv_rows" in partial:
            take(0, partial)
        rows_out.flush_rest()
        rows_out.finish()
        kept = sum(1 for _, s, _ in statuses if s != "interrupted")
        if isinstance(e, cluster.Failed):
            print("sweep: %s: kept the %d finished cases" % (e, kept), file=sys.stderr)
            return 5
        print("sweep: interrupted: kept the %d finished cases%s" % (
            kept, " (the cluster's tasks were cancelled)" if client else ""), file=sys.stderr)
        return 128 + (e.signum if isinstance(e, Stop) else signal.SIGINT)
    except BrokenPipeError:
        raise
    except OSError as e:
        print("sweep: writing %s failed: %s" % (rows_out.name, e.strerror or e), file=sys.stderr)
        return 4
    if progress:
        progress.finish()
    rows_out.finish()
    failed = sorted((i, e) for i, s, e in statuses if s != "ok")
    for i, error in failed[:5]:
        print("warning: case %d: %s" % (i, error), file=sys.stderr)
    print("swept %d cases (%d not ok) of %g s each%s: wall time %.3g s"
          % (len(statuses), len(failed), args["duration"],
             " on %s in tasks of %d" % (args["scheduler"], chunk) if client else "",
             time.monotonic() - start), file=sys.stderr)
    return 3 if failed else 0
