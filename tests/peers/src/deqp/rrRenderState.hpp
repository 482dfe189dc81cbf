#ifndef _RRRENDERSTATE_HPP
#define _RRRENDERSTATE_HPP
/*-------------------------------------------------------------------------
 * drawElements Quality Program Reference Renderer
 * -----------------------------------------------
 *
 * Copyright 2014 The Android Open Source Project
 *
 * Licensed under the Apache License, Version 2.0 (the "License");
 * you may not use this file except in compliance with the License.
 * You may obtain a copy of the License at
 *
 *      http://www.apache.org/licenses/LICENSE-2.0
 *
 * Unless required by applicable law or agreed to in writing, software
 * distributed under the License is distributed on an "AS IS" BASIS,
 * WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 * See the License for the specific language governing permissions and
 * limitations under the License.
 *
 *//*!
 * \file
 * \brief Reference renderer render state.
 *//*--------------------------------------------------------------------*/


/* rastercheck: trimmed to the rasterization enums and RasterizationState (lines 34-90 of the
   original, unchanged); the rest of the render state is not needed by rrRasterizer.cpp. */

#include "rrDefs.hpp"

namespace rr
{

enum HorizontalFill
{
    FILL_LEFT,
    FILL_RIGHT
};

//! Vertical fill rule
enum VerticalFill
{
    FILL_TOP,
    FILL_BOTTOM,
};

//! Winding mode
enum Winding
{
    WINDING_CCW = 0, //!< Counter-clockwise winding
    WINDING_CW,      //!< Clockwise winding

    WINDING_LAST
};

//! Triangle cull mode
enum CullMode
{
    CULLMODE_NONE,
    CULLMODE_BACK,
    CULLMODE_FRONT,
    CULLMODE_FRONT_AND_BACK,

    CULLMODE_LAST
};

//! Viewport Orientation of renderer this will be compared against
enum ViewportOrientation
{
    VIEWPORTORIENTATION_LOWER_LEFT = 0, //<! Corresponds to GL
    VIEWPORTORIENTATION_UPPER_LEFT,     //<! Corresponds to Vulkan

    VIEWPORTORIENTATION_LAST
};

struct RasterizationState
{
    RasterizationState(void)
        : winding(WINDING_CCW)
        , horizontalFill(FILL_LEFT)
        , verticalFill(FILL_BOTTOM)
        , viewportOrientation(VIEWPORTORIENTATION_LAST)
    {
    }

    Winding winding;
    HorizontalFill horizontalFill;
    VerticalFill verticalFill;
    ViewportOrientation viewportOrientation;
};

} // namespace rr

#endif // _RRRENDERSTATE_HPP
