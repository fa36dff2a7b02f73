// A tree source reaching up into struts/: the wrong way (layers.wrong_way_fails).
#include "tree/grow.hpp"
#include "struts/struts.hpp"
