#pragma once
/// @file
/// Number formatting for configuration error messages.

#include <string>

namespace retreat::model {

/// The shortest decimal text that reads back as exactly @p value (`0.1`, `-3`, `1e-09`,
/// `nan`, `inf`), so that an error message shows the value as the user wrote it.
std::string format_number(double value);

}  // namespace retreat::model
