"""The monitor node made in the test's own process (its parameters given as ROS arguments) and what it
subscribes to: shared by the node tests (import the fixture `node_of` into a test module to use it)."""
import pytest
import rclpy
from rclpy.signals import SignalHandlerOptions


@pytest.fixture
def node_of():
    made = []

    def make(*parameters):
        from railderail_monitor.node import MonitorNode
        rclpy.init(args=["--ros-args", *[a for p in parameters for a in ("-p", p)]],
                   signal_handler_options=SignalHandlerOptions.NO)
        made.append(MonitorNode())
        return made[-1]
    yield make
    for node in made:
        node.destroy_node()
    rclpy.try_shutdown()


def subscribed(node):
    """The topics the node subscribes to."""
    return {topic for topic, _ in node.get_subscriber_names_and_types_by_node(node.get_name(), node.get_namespace())}
