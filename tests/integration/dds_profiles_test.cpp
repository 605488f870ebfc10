// (being written)
#include <gtest/gtest.h>
TEST(DdsProfiles, Placeholder) {}
