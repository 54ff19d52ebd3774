/* overlay.c -- (being written) */
#include "render_priv.h"
