/* Colours for renders: names and hex accepted on the command line, and a
 * default palette so every layer is told apart without choosing. */
#include "core/common.h"
#include "dpoints_tools.h"

#include <ctype.h>
#include <stddef.h>
#include <strings.h>

typedef struct named_colour {
	const char *name;
	unsigned char rgb[3];
} named_colour;

static const named_colour names[] = {
	{ "red", { 214, 39, 40 } },
	{ "green", { 44, 160, 44 } },
	{ "blue", { 31, 119, 180 } },
	{ "orange", { 255, 127, 14 } },
	{ "purple", { 148, 103, 189 } },
	{ "yellow", { 230, 200, 20 } },
	{ "cyan", { 23, 190, 207 } },
	{ "magenta", { 220, 40, 200 } },
	{ "pink", { 227, 119, 194 } },
	{ "brown", { 140, 86, 75 } },
	{ "grey", { 127, 127, 127 } },
	{ "gray", { 127, 127, 127 } },
	{ "black", { 0, 0, 0 } },
	{ "white", { 255, 255, 255 } },
};

/* Ordered so that consecutive layers (input, skeleton, surface, ...) differ
 * most in hue; none is pale enough to vanish on white. */
static const unsigned char palette[][3] = {
	{ 31, 119, 180 },  /* blue */
	{ 255, 127, 14 },  /* orange */
	{ 44, 160, 44 },   /* green */
	{ 214, 39, 40 },   /* red */
	{ 148, 103, 189 }, /* purple */
	{ 140, 86, 75 },   /* brown */
	{ 227, 119, 194 }, /* pink */
	{ 23, 190, 207 },  /* cyan */
};

#define PALETTE_SIZE (sizeof palette / sizeof palette[0])

static int hex_digit(char c)
{
	if (c >= '0' && c <= '9')
		return c - '0';
	c = (char)tolower((unsigned char)c);
	if (c >= 'a' && c <= 'f')
		return c - 'a' + 10;
	return -1;
}

/* #rgb or #rrggbb: `digits` is 1 or 2 hex digits per channel. */
static int parse_hex(const char *hex, size_t digits, unsigned char rgb[3])
{
	unsigned char out[3];
	for (size_t c = 0; c < 3; c++) {
		int value = 0;
		for (size_t k = 0; k < digits; k++) {
			int d = hex_digit(hex[c * digits + k]);
			if (d < 0)
				return -1;
			value = value * 16 + d;
		}
		/* #f80 means #ff8800, as in CSS. */
		out[c] = (unsigned char)(digits == 1 ? value * 17 : value);
	}
	for (size_t c = 0; c < 3; c++)
		rgb[c] = out[c];
	return 0;
}

/* 0 and rgb filled, or -1 */
static int parse(const char *text, unsigned char rgb[3])
{
	if (text[0] == '#') {
		size_t len = 0;
		while (text[1 + len])
			len++;
		if (len == 3 || len == 6)
			return parse_hex(text + 1, len / 3, rgb);
		return -1;
	}
	for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
		if (strcasecmp(text, names[i].name) == 0) {
			for (int c = 0; c < 3; c++)
				rgb[c] = names[i].rgb[c];
			return 0;
		}
	}
	return -1;
}

dp_status dp_parse_colour(const char *text, unsigned char rgb[3], dp_error *err)
{
	if (!text || !rgb)
		return dp_fail(err, DP_ERR_ARG, "colour: NULL text or rgb");
	if (parse(text, rgb) != 0)
		return dp_fail(err, DP_ERR_ARG, "colour: '%s' is neither a colour name nor #rgb / #rrggbb", text);
	return DP_OK;
}

void dp_render_default_colour(size_t index, unsigned char rgb[3])
{
	const unsigned char *c = palette[index % PALETTE_SIZE];
	rgb[0] = c[0];
	rgb[1] = c[1];
	rgb[2] = c[2];
}
