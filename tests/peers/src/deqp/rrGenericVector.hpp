#ifndef _RRGENERICVECTOR_HPP
#define _RRGENERICVECTOR_HPP
/* rastercheck's stand-in: rrFragmentPacket.hpp needs only tcu::IVec2 and tcu::Vec4 from here. */
#include "rrDefs.hpp"
#include "tcuVector.hpp"
#endif
