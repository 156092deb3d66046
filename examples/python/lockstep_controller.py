#!/usr/bin/python3
"""A lockstep controller in rospy: answers every joint_states with torque_command_stamped
carrying that message's own stamp (never now(): the node matches answers by stamp), here the
PD law M_m = kp (setpoint - q1) - kd u1, clamped. Start the node with lockstep:=true."""
import rospy
from sensor_msgs.msg import JointState
from kane_sim.msg import TorqueCommandStamped


def main():
    rospy.init_node("lockstep_controller")
    kp, kd = rospy.get_param("~kp", 500.0), rospy.get_param("~kd", 30.0)
    limit, setpoint = rospy.get_param("~torque_limit", 50.0), rospy.get_param("~setpoint", 1.0)
    pub = rospy.Publisher("torque_command_stamped", TorqueCommandStamped, queue_size=10,
                          tcp_nodelay=True)

    def answer(state):
        crank = next(i for i, name in enumerate(state.name) if name.endswith("crank_joint"))
        torque = kp * (setpoint - state.position[crank]) - kd * state.velocity[crank] + 0.0
        reply = TorqueCommandStamped(torque=max(-limit, min(limit, torque)))
        reply.header.stamp = state.header.stamp  # the state answered: copy its stamp
        pub.publish(reply)

    rospy.Subscriber("joint_states", JointState, answer, queue_size=10, tcp_nodelay=True)
    rospy.spin()


if __name__ == "__main__":
    main()
