#include "node_interfaces.h"

#include <algorithm>

namespace kane_sim {

void NodeInterfaces::shutdown() {
  for (ros::Subscriber* sub : {&torque_command, &torque_command_stamped, &servo_setpoint})
    sub->shutdown();
  for (ros::Publisher* pub :
       {&joint_states, &joint_states_true, &mechanism_state, &servo_state, &markers, &clock,
        &diagnostics, &reset_event, &input_log, &checkpoint, &tf})
    pub->shutdown();
  for (ros::ServiceServer& service : services) service.shutdown();
  services.clear();
  static_tf.reset();
  tf_subscribers_ = 0;
}

void NodeInterfaces::publishTf(const tf2_msgs::TFMessage& transforms, const ros::Time& stamp) {
  if (!tf) return;
  const uint32_t subscribers = tf.getNumSubscribers();
  if (stamp > last_tf_stamp_ || subscribers > tf_subscribers_) tf.publish(transforms);
  last_tf_stamp_ = std::max(last_tf_stamp_, stamp);
  tf_subscribers_ = subscribers;
}

}  // namespace kane_sim
