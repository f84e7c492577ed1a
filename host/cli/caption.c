/* Captions drawn into rendered pictures: a picture passed around without its
 * command line should still say what it shows. A 3x5 pixel font, drawn at
 * an integer scale, is enough for file names, counts and view angles, and
 * needs no font library. */
#include "cli/caption.h"

#include <ctype.h>
#include <math.h>
#include <string.h>

/* Rows top to bottom, three columns each; '#' is ink. Lower case is drawn
 * as upper case, and a character without a glyph as '?'. */
static const struct {
	char c;
	char rows[5][4];
} glyphs[] = {
	{' ', {"...", "...", "...", "...", "..."}},
	{'A', {".#.", "#.#", "###", "#.#", "#.#"}},
	{'B', {"##.", "#.#", "##.", "#.#", "##."}},
	{'C', {".##", "#..", "#..", "#..", ".##"}},
	{'D', {"##.", "#.#", "#.#", "#.#", "##."}},
	{'E', {"###", "#..", "##.", "#..", "###"}},
	{'F', {"###", "#..", "##.", "#..", "#.."}},
	{'G', {".##", "#..", "#.#", "#.#", ".##"}},
	{'H', {"#.#", "#.#", "###", "#.#", "#.#"}},
	{'I', {"###", ".#.", ".#.", ".#.", "###"}},
	{'J', {"..#", "..#", "..#", "#.#", ".#."}},
	{'K', {"#.#", "#.#", "##.", "#.#", "#.#"}},
	{'L', {"#..", "#..", "#..", "#..", "###"}},
	{'M', {"#.#", "###", "###", "#.#", "#.#"}},
	{'N', {"##.", "#.#", "#.#", "#.#", "#.#"}},
	{'O', {".#.", "#.#", "#.#", "#.#", ".#."}},
	{'P', {"##.", "#.#", "##.", "#..", "#.."}},
	{'Q', {".#.", "#.#", "#.#", "##.", ".##"}},
	{'R', {"##.", "#.#", "##.", "#.#", "#.#"}},
	{'S', {".##", "#..", ".#.", "..#", "##."}},
	{'T', {"###", ".#.", ".#.", ".#.", ".#."}},
	{'U', {"#.#", "#.#", "#.#", "#.#", "###"}},
	{'V', {"#.#", "#.#", "#.#", "#.#", ".#."}},
	{'W', {"#.#", "#.#", "###", "###", "#.#"}},
	{'X', {"#.#", "#.#", ".#.", "#.#", "#.#"}},
	{'Y', {"#.#", "#.#", ".#.", ".#.", ".#."}},
	{'Z', {"###", "..#", ".#.", "#..", "###"}},
	{'0', {"###", "#.#", "#.#", "#.#", "###"}},
	{'1', {".#.", "##.", ".#.", ".#.", "###"}},
	{'2', {"##.", "..#", ".#.", "#..", "###"}},
	{'3', {"##.", "..#", ".#.", "..#", "##."}},
	{'4', {"#.#", "#.#", "###", "..#", "..#"}},
	{'5', {"###", "#..", "##.", "..#", "##."}},
	{'6', {".##", "#..", "###", "#.#", "###"}},
	{'7', {"###", "..#", ".#.", ".#.", ".#."}},
	{'8', {"###", "#.#", "###", "#.#", "###"}},
	{'9', {"###", "#.#", "###", "..#", "##."}},
	{'.', {"...", "...", "...", "...", ".#."}},
	{',', {"...", "...", "...", ".#.", "#.."}},
	{':', {"...", ".#.", "...", ".#.", "..."}},
	{'-', {"...", "...", "###", "...", "..."}},
	{'_', {"...", "...", "...", "...", "###"}},
	{'/', {"..#", "..#", ".#.", "#..", "#.."}},
	{'(', {".#.", "#..", "#..", "#..", ".#."}},
	{')', {".#.", "..#", "..#", "..#", ".#."}},
	{'[', {"##.", "#..", "#..", "#..", "##."}},
	{']', {".##", "..#", "..#", "..#", ".##"}},
	{'#', {"#.#", "###", "#.#", "###", "#.#"}},
	{'+', {"...", ".#.", "###", ".#.", "..."}},
	{'=', {"...", "###", "...", "###", "..."}},
	{'%', {"#.#", "..#", ".#.", "#..", "#.#"}},
	{'\'', {".#.", ".#.", "...", "...", "..."}},
	{'?', {"##.", "..#", ".#.", "...", ".#."}},
	{'!', {".#.", ".#.", ".#.", "...", ".#."}},
	{'*', {"...", "#.#", ".#.", "#.#", "..."}},
	{'<', {"..#", ".#.", "#..", ".#.", "..#"}},
	{'>', {"#..", ".#.", "..#", ".#.", "#.."}},
};

static const char (*glyph(char c))[4]
{
	c = (char)toupper((unsigned char)c);
	for (size_t i = 0; i < sizeof glyphs / sizeof glyphs[0]; i++)
		if (glyphs[i].c == c)
			return glyphs[i].rows;
	return NULL;
}

int dp_cli_caption_scale(int view_width)
{
	int s = view_width / 256;
	return s < 1 ? 1 : s > 4 ? 4 : s;
}

int dp_cli_caption_width(const char *text, int scale)
{
	return (int)strlen(text) * 4 * scale;
}

void dp_cli_draw_text(unsigned char *rgb, int w, int h, int x, int y, int max_x, const char *text, int scale,
		      const unsigned char ink[3])
{
	for (const char *p = text; *p; p++, x += 4 * scale) {
		if (x + 3 * scale > max_x)
			return;
		const char(*rows)[4] = glyph(*p);
		if (!rows)
			rows = glyph('?');
		for (int r = 0; r < 5; r++)
			for (int c = 0; c < 3; c++) {
				if (rows[r][c] != '#')
					continue;
				for (int dy = 0; dy < scale; dy++)
					for (int dx = 0; dx < scale; dx++) {
						int px = x + c * scale + dx, py = y + r * scale + dy;
						if (px >= 0 && px < w && py >= 0 && py < h)
							memcpy(rgb + 3 * ((size_t)py * (size_t)w + (size_t)px), ink, 3);
					}
			}
	}
}

/* The vertical axis where the data does not say otherwise: y (the Stanford
 * scans and most meshes), unless the z extent clearly exceeds the y extent,
 * as in z-up scans of upright things (lampposts, people, buildings). Lying
 * z-up data (a flat terrain) still gets y: --up says so. */
int dp_cli_detect_up(const dp_cloud *clouds, size_t n)
{
	double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
	for (size_t l = 0; l < n; l++)
		for (size_t i = 0; i < clouds[l].n; i++) {
			const float p[3] = {clouds[l].x[i], clouds[l].y[i], clouds[l].z[i]};
			for (int a = 0; a < 3; a++)
				if (isfinite(p[a])) {
					lo[a] = fmin(lo[a], p[a]);
					hi[a] = fmax(hi[a], p[a]);
				}
		}
	double ey = hi[1] - lo[1], ez = hi[2] - lo[2];
	return ez > 1.2 * ey ? 2 : 1;
}
