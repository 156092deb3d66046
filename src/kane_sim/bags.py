"""Opening a bag and finding its topics, once for the package: plot_bag, bag_summary, loop_bag
and identify (through rosbag's C++ reader, kane_sim._bag) read bags through here, so a device,
a garbage file or a missing rosbag gets one message wherever it is given. Imports nothing but the standard library until a bag is opened."""
import os


def _regular_file(path):
    """ValueError unless path is a regular file: a device such as /dev/zero or a pipe would be
    read without end."""
    if not os.path.isfile(path):
        raise ValueError("%s is not a regular file (%s)" % (
            path, "no such file" if not os.path.exists(path) else "a device, a pipe or a folder"))


def open_bag(path):
    """rosbag.Bag(path) for reading, or ValueError naming the path and why: not a regular file,
    no rosbag module, or not a bag rosbag can read (truncated, garbage)."""
    _regular_file(path)
    try:
        import rosbag
    except ImportError:
        raise ValueError("reading %s needs rosbag (python3-rosbag)" % path) from None
    try:
        return rosbag.Bag(path)
    except Exception as e:  # rosbag raises its own ROSBagException, and others on garbage
        raise ValueError("%s is not a readable bag: %s" % (path, e)) from None


def topic_types(path):
    """{topic: message type} of the bag at path, read by rosbag's C++ reader (kane_sim._bag: an
    hour of 1 kHz messages is an index rosbag's Python reader takes minutes and gigabytes over);
    ValueError as open_bag's."""
    _regular_file(path)
    from kane_sim import _bag
    return _bag.topic_types(path)


def topics_of_type(types, msg_type):
    """The topics of `types` ({topic: message type}) carrying `msg_type`, sorted."""
    return sorted(t for t, kind in types.items() if kind == msg_type)


def choose_topic(types, path, msg_type, suffix, topic=None, flag="topic="):
    """The topic to read of a bag whose topics are `types` ({topic: message type}, topic_types):
    `topic` when given (checked to exist and carry msg_type), else the one topic of that type
    whose name ends in `suffix`. ValueError naming the candidates otherwise."""
    candidates = topics_of_type(types, msg_type)
    listed = ", ".join(candidates) or "none"
    if topic is None:
        named = [t for t in candidates if t.rstrip("/").endswith(suffix)]
        if not named:
            other = sorted(t for t in types if t.rstrip("/").endswith(suffix))
            if other:  # the name is there, with another type
                raise ValueError("%s's topic %s is %s, not %s (%s topics: %s)"
                                 % (path, other[0], types[other[0]], msg_type, msg_type, listed))
            raise ValueError("%s has no %s topic (%s topics: %s)"
                             % (path, suffix, msg_type, listed))
        if len(named) > 1:
            raise ValueError("%s has %d %s topics (%s): name one with %s"
                             % (path, len(named), suffix, ", ".join(named), flag))
        return named[0]
    if topic not in types:
        raise ValueError("%s has no topic %s (%s topics: %s)" % (path, topic, msg_type, listed))
    if topic not in candidates:
        raise ValueError("%s's topic %s is %s, not %s (%s topics: %s)"
                         % (path, topic, types[topic], msg_type, msg_type, listed))
    return topic
