// The display model and colour measures of the separation score (analysis/separation.h,
// docs/separation.md): what a viewer of a rendering's 8-bit image sees, in the units the
// perceptual measures are defined in.
//
// Display: the image's display-linear sRGB value x (the scene's exposure applied) goes through the
// scene's tone curve (core/rgb_image.h) and is clipped to [0, 1]; the display shows it with the
// sRGB primaries and D65 white (IEC 61966-2-1) at `peak` cd/m² for (1, 1, 1) (100 cd/m² by
// default, the sRGB reference display's 80 rounded up to a typical office monitor's lowest
// setting). 8-bit quantisation is not modelled.
#pragma once

#include <array>
#include <string>

namespace lobe {

using Rgb3 = std::array<double, 3>;

// Relative luminance of linear sRGB (IEC 61966-2-1, the BT.709 Y row: 0.2126, 0.7152, 0.0722).
inline double srgbLuminance(double r, double g, double b) {
    return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

// A display-linear value as displayed: tone curve ("clip" or "shoulder"), then clipped to [0, 1].
// Throws lobe::Error for an unknown curve.
double displayed(double linear, const std::string& tone);
// The same with the curve looked up once (toneIsShoulder: "clip" → false, "shoulder" → true).
double displayedShoulder(double linear, bool shoulder);
bool toneIsShoulder(const std::string& tone);

// CIE 1976 L*a*b* (CIE 15:2004, §8.2.1) of displayed linear sRGB, white = the display's white
// (1, 1, 1) = D65. XYZ from linear sRGB with the IEC 61966-2-1 matrix.
Rgb3 srgbToLab(const Rgb3& rgb);

// ICtCp (ITU-R BT.2100, Table 6/7) of displayed linear sRGB on a display of `peak` cd/m²:
//   BT.709 → BT.2020 primaries (ITU-R BT.2087, §2), × peak / 10000, LMS (BT.2100),
//   PQ inverse EOTF (SMPTE ST 2084), then I, Ct, Cp.
Rgb3 srgbToIctcp(const Rgb3& rgb, double peak);

// ΔE_ITP = 720 · √(ΔI² + (0.5 ΔCt)² + ΔCp²)  (ITU-R BT.2124, eq. 1: T = 0.5 Ct, P = Cp);
// 1 is about one just-noticeable difference.
double deltaEItp(const Rgb3& ictcpA, const Rgb3& ictcpB);

}  // namespace lobe
