#ifndef _TCUVECTORUTIL_HPP
#define _TCUVECTORUTIL_HPP
/* rastercheck's stand-in for dEQP's tcuVectorUtil.hpp: the helpers defined in tcuVector.hpp. */
#include "tcuVector.hpp"
#endif
