// A struts source using the tree below it: the right way.
#include "tree/grow.hpp"
