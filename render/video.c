/* video.c -- (being written) */
#include "render_priv.h"
