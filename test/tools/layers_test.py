#!/usr/bin/python3
"""The layers are what CMake links: every source and header of a target includes kane_sim headers
only from itself and from the targets it links (transitively). Reads CMakeLists.txt:
add_library / add_executable give each target its files, target_sources(T INTERFACE ...) the
headers of a header-only target, target_link_libraries its dependencies; a header not listed
belongs to the library of its folder (include/kane_sim/<layer>/ -> kane_sim_<layer>).
kane_sim/format_number.h is shared by all. Private headers a file includes from its own folder
are scanned as part of its target. A ROS-free target (kane_sim_ros_free in CMake) may include no
ROS header and no message header: on Debian ROS's headers are on the default include path, so
the build alone would not notice. Also checks that doc/design/architecture.md names each
library's dependencies as CMake declares them.

Usage: layers_test.py [SOURCE_DIR]   (exit 1 with one line per violation)
"""
import os
import re
import sys

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
SHARED = {"kane_sim/format_number.h"}
# The message headers catkin generates for this package: only the ROS layer and nodes see them.
GENERATED = re.compile(r"kane_sim/[A-Z]\w*\.h$")
# ROS's own headers: on Debian they sit on the default include path (/usr/include/ros, ...), so a
# ROS-free layer that includes one would still compile; this test is what keeps them out.
ROS_HEADER = re.compile(
    r"#include <(ros|rosbag|rospy|roscpp|tf2|tf2_ros|tf2_msgs|std_msgs|std_srvs|sensor_msgs|"
    r"geometry_msgs|visualization_msgs|rosgraph_msgs|diagnostic_msgs|diagnostic_updater|"
    r"dynamic_reconfigure|interactive_markers|urdf|xmlrpcpp|actionlib|message_filters)/")


def commands(text, name):
    """The argument lists of every call of CMake command `name`."""
    text = re.sub(r"#[^\n]*", "", text)
    return [m.group(1).split() for m in re.finditer(name + r"\(([^)]*)\)", text)]


def main():
    cmake = open(os.path.join(ROOT, "CMakeLists.txt")).read()
    # Source lists kept in variables (cmake/ros_free_sources.cmake, shared with the WebAssembly
    # build) are expanded where a target names them.
    variables = {}
    for name in sorted(os.listdir(os.path.join(ROOT, "cmake"))):
        if name.endswith(".cmake"):
            for args in commands(open(os.path.join(ROOT, "cmake", name)).read(), "set"):
                variables[args[0]] = args[1:]
    cmake = re.sub(r"\$\{(\w+)\}", lambda m: " ".join(variables.get(m.group(1), [m.group(0)])),
                   cmake)
    files = {}  # target -> its source files and listed headers
    libraries = {args[0] for args in commands(cmake, "add_library")} - {"kane_sim_warnings"}
    for args in commands(cmake, "add_library") + commands(cmake, "add_executable"):
        files[args[0]] = [a for a in args[1:] if re.search(r"\.(cpp|h)$", a)]
    ros_free = {args[0] for args in commands(cmake, "kane_sim_ros_free")}
    for args in commands(cmake, "target_sources"):
        files.setdefault(args[0], []).extend(a for a in args[2:] if a.endswith(".h"))
    links = {t: set() for t in files}
    for args in commands(cmake, "target_link_libraries"):
        if args[0] in links:
            links[args[0]].update(a for a in args[1:] if a in files)
    # Headers not listed with a target belong to their folder's library.
    listed = {f for fs in files.values() for f in fs}
    for target in files:
        m = re.match(r"kane_sim_(\w+)$", target)
        folder = os.path.join(ROOT, "include", "kane_sim", m.group(1)) if m else None
        if folder and os.path.isdir(folder):
            for h in sorted(os.listdir(folder)):
                path = "include/kane_sim/%s/%s" % (m.group(1), h)
                if path not in listed:
                    files[target].append(path)
    owner = {}
    for target, fs in files.items():
        for f in fs:
            if f.startswith("include/"):
                owner[f[len("include/"):]] = target

    def closure(target, seen=None):
        seen = set() if seen is None else seen
        for dep in links.get(target, ()):
            if dep not in seen:
                seen.add(dep)
                closure(dep, seen)
        return seen

    problems = []
    for target, fs in sorted(files.items()):
        allowed = closure(target) | {target}
        for f in fs:
            # Private headers are part of the target that includes them: the one beside a
            # source, and every "x.h" a file includes from its own folder (integrator.h,
            # outputs.h, python_layer.h, ...), followed as far as they go.
            paths = [f]
            local = os.path.splitext(f)[0] + ".h"
            if f.endswith(".cpp") and local not in fs and os.path.exists(os.path.join(ROOT, local)):
                paths.append(local)
            for path in paths:
                for line_no, line in enumerate(open(os.path.join(ROOT, path)), 1):
                    if target in ros_free and ROS_HEADER.match(line):
                        problems.append("%s:%d: %s in ROS-free %s"
                                        % (path, line_no, line.strip(), target))
                    private = re.match(r'#include "([^"/]+\.h)"', line)
                    if private:
                        beside = os.path.join(os.path.dirname(path), private.group(1))
                        if os.path.exists(os.path.join(ROOT, beside)) and beside not in paths:
                            paths.append(beside)
                    m = re.match(r'#include "(kane_sim/[^"]+)"', line)
                    if not m or m.group(1) in SHARED:
                        continue
                    header = m.group(1)
                    if GENERATED.match(header):
                        if target in ros_free:
                            problems.append("%s:%d: %s (a ROS message) in ROS-free %s"
                                            % (path, line_no, header, target))
                        continue
                    if header not in owner:
                        problems.append("%s:%d: %s belongs to no target" % (path, line_no, header))
                    elif owner[header] not in allowed:
                        problems.append("%s:%d: %s of %s, which %s does not link"
                                        % (path, line_no, header, owner[header], target))

    # doc/design/architecture.md's table of libraries says what each links.
    doc = open(os.path.join(ROOT, "doc", "design", "architecture.md")).read()
    for target in sorted(libraries):
        m = re.search(r"^\s*\| `%s` \| ([^|]*) \|" % target, doc, re.M)
        if not m:
            problems.append("doc/design/architecture.md: no row for %s in the table of libraries"
                            % target)
            continue
        documented = set(re.findall(r"kane_sim_\w+", m.group(1)))
        declared = links[target] - {"kane_sim_warnings"}
        if documented != declared:
            problems.append("doc/design/architecture.md: %s links %s, the doc says %s"
                            % (target, sorted(declared) or "nothing of ours",
                               sorted(documented) or "nothing"))
    for p in problems:
        print(p)
    print("layers: %d targets, %d problems" % (len(files), len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
