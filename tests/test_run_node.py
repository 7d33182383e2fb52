"""run_node's Ctrl-C and SIGTERM around rclpy's events executor, made deterministic: the signal is sent from inside
the process at a chosen read of a subscription's `handle` (the events executor reads it, in Python, when it takes
the node's subscriptions in at its first spin and when it lets them go at its shutdown)."""
import signal
import sys

import pytest

NODE = """
import os, signal, sys
from rclpy.node import Node
from rclpy.subscription import Subscription
from std_msgs.msg import String
from railderail_sim.ros import interface as m

at = int(sys.argv[1])       # the read of a subscription's handle at which this process gets a Ctrl-C
reads = [0]
handle = Subscription.handle.fget


def counted(self):
    reads[0] += 1
    if reads[0] == at:
        os.kill(os.getpid(), signal.SIGINT)
    if reads[0] == 3:
        print("[probe] taken in", file=sys.stderr, flush=True)
    return handle(self)


Subscription.handle = property(counted)


class Probe(Node):
    def __init__(self):
        super().__init__("railderail_test_probe")
        for topic in ("a", "b", "c"):   # three subscriptions: reads 1-3 at the first spin, 4-6 at the shutdown
            self.create_subscription(String, "/railderail_test/" + topic, lambda msg: None, 10)

    def destroy_node(self):
        print("[probe] summary", file=sys.stderr, flush=True)
        super().destroy_node()


sys.exit(m.run_node("probe", Probe, executor_class=m.events_executor))
"""


@pytest.mark.parametrize("at", [2, 3])
def test_ctrl_c_while_the_events_executor_takes_the_node_in(at, spawn):
    """A KeyboardInterrupt raised there left a callback registered that the executor no longer knew of, and its
    destructor aborted the process (SIGABRT, "Destroying callback manager with callbacks remaining")."""
    child = spawn([sys.executable, "-c", NODE, str(at)])
    assert child.wait(timeout=60) == 0, child.stderr.read()
    assert "[probe] summary" in child.stderr.read()


def test_ctrl_c_during_the_teardown_does_not_cut_it_short(spawn, read_until):
    """SIGTERM, then a Ctrl-C while the executor shuts down: the teardown ends as if there were one signal."""
    child = spawn([sys.executable, "-c", NODE, "4"])
    read_until(child, "[probe] taken in", timeout=60)
    child.send_signal(signal.SIGTERM)
    assert child.wait(timeout=30) == 0, child.stderr.read()
    err = child.stderr.read()
    assert "[probe] summary" in err and "KeyboardInterrupt" not in err


RECORDER = """
import os, signal, sys, time
import rclpy.duration
from railderail_sim.ros import interface as m
from railderail_monitor.recording import recorder

write = recorder.McapRecording.write


def interrupted(self, topic, data):      # Ctrl-C as the recorder writes the first message
    write(self, topic, data)
    if self.messages == 1:
        os.kill(os.getpid(), signal.SIGINT)


recorder.McapRecording.write = interrupted


def make():
    node = recorder.RecorderNode(sys.argv[1], log=lambda text: print(text, file=sys.stderr, flush=True))
    _, cls, qos, _ = m.TOPICS[m.STATES]
    pub = node.create_publisher(cls, m.STATES, qos)
    while pub.get_subscription_count() < 1:
        time.sleep(0.01)
    for k in range(500):                 # sent and acknowledged, not yet taken: the recorder has not spun
        msg = cls()
        msg.header.stamp.nanosec = k
        pub.publish(msg)
    assert pub.wait_for_all_acked(rclpy.duration.Duration(seconds=10))
    return node


sys.exit(m.run_node("probe", make))
"""


def test_a_recorder_stopped_writes_what_its_queues_hold(spawn, tmp_path):
    """Stopped while its queues hold messages the transport delivered (a recorder behind the simulator at the run's
    end), the recorder writes them all before it closes the file and says so: stopped at once, it lost them."""
    from mcap.reader import make_reader
    out = tmp_path / "run.mcap"
    child = spawn([sys.executable, "-c", RECORDER, str(out)])
    assert child.wait(timeout=60) == 0, child.stderr.read()
    assert "(499 of them still queued at the stop)" in child.stderr.read()
    with open(out, "rb") as f:
        stamps = [message.log_time for _, channel, message in make_reader(f).iter_messages()
                  if channel.topic.endswith("states")]
    assert stamps == list(range(500))
