// A callback queue that calls each callback at once, in the thread that delivered it (roscpp's
// network thread), instead of queueing it for ros::spin's thread. At 1 kHz this saves a thread
// wake-up per message: roscpp otherwise signals a condition variable for every message and the
// spinner wakes to take it, which costs more than a short callback. The callbacks given to one
// queue run one at a time, as under a single-threaded spinner, so they may share state without a
// lock of their own; they must be short (they hold up the network thread) and must not subscribe or
// unsubscribe. Subscriptions only, not timers: roscpp's timer thread queues a timer's callback with
// its own locks held, and the callback, called there, reschedules the timer under the same lock. A
// timer (on ros::spin's queue) that shares the subscriptions' state takes hold() first.
#ifndef KANE_SIM_ROS_INLINE_CALLBACK_QUEUE_H
#define KANE_SIM_ROS_INLINE_CALLBACK_QUEUE_H

#include <functional>
#include <mutex>
#include <string>
#include <utility>

#include <ros/callback_queue_interface.h>
#include <ros/ros.h>

namespace kane_sim {

class InlineCallbackQueue : public ros::CallbackQueueInterface {
 public:
  void addCallback(const ros::CallbackInterfacePtr& callback, uint64_t /*owner_id*/) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    // Invalid: the subscription is gone. TryAgain cannot happen: every call of a
    // callback on this queue is made under this lock.
    if (callback->ready()) callback->call();
  }
  void removeByID(uint64_t /*owner_id*/) override {}  // nothing is held

  // nh.subscribe with this queue: callback(const M::ConstPtr&) runs in the network thread.
  template <class M>
  ros::Subscriber subscribe(ros::NodeHandle& nh, const std::string& topic, uint32_t queue_size,
                            std::function<void(const typename M::ConstPtr&)> callback,
                            const ros::TransportHints& hints = ros::TransportHints()) {
    ros::SubscribeOptions options;
    options.init<M>(topic, queue_size, std::move(callback));
    options.transport_hints = hints;
    options.callback_queue = this;
    return nh.subscribe(options);
  }

  // While the returned lock lives, no callback of this queue runs.
  std::unique_lock<std::mutex> hold() { return std::unique_lock<std::mutex>(mutex_); }

 private:
  std::mutex mutex_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_INLINE_CALLBACK_QUEUE_H
