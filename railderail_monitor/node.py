"""Monitor node: placeholder and starting point for the monitor node.

For now it only starts, logs one line and spins until Ctrl-C (SIGINT) or SIGTERM, so that the
`railderail-monitor` command and `ros2 run railderail monitor` resolve. The real node (subscribing
to the simulator's topics, evaluating the derailment criteria and publishing alerts) replaces the
body of `main`.
"""
import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node


def main() -> int:
    rclpy.init()
    node = None
    try:  # from here on, Ctrl-C (KeyboardInterrupt) or SIGTERM ends the node cleanly
        node = Node("railderail_monitor")
        node.get_logger().info("railderail monitor node started (placeholder: subscribes to nothing yet)")
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0
