// interval/interval.cpp — compile-time checks that the interval types meet the number concepts.
#include "interval/interval.h"

#include "interval/number.h"

namespace certray {

static_assert(Number<double>);
static_assert(Enclosure<Interval>);
static_assert(Enclosure<UpInterval>);

}  // namespace certray
