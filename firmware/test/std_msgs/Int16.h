// Test double of ros_lib's generated std_msgs/Int16.h: the data field, as rosserial has it.
#ifndef FAKE_STD_MSGS_INT16_H
#define FAKE_STD_MSGS_INT16_H

#include <stdint.h>

#include "../ros.h"

namespace std_msgs {

class Int16 : public ros::Msg
{
public:
  typedef int16_t _data_type;
  _data_type data;

  Int16() : data(0) {}
  long fake_value() const { return data; }
};

}  // namespace std_msgs

#endif  // FAKE_STD_MSGS_INT16_H
