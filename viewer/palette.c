// The GIF palette (palette.h).
#include "palette.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define FV_GREY_LEVELS 32
#define FV_CUBE_LEVELS 4
#define FV_BINS 32768
#define FV_SATURATION 12 // max - min channel at or below which a pixel counts as grey

// A histogram bin of 5-bit RGB with its pixel count.
typedef struct fvBin
{
	unsigned char rgb[3];
	long count;
} fvBin;

// A box of bins [first, last) in the bin array.
typedef struct fvBox
{
	int first, last;
} fvBox;

static int fvSortChannel; // the channel fvCompareBins orders by (qsort has no context)

static int fvCompareBins(const void* a, const void* b)
{
	return (int)((const fvBin*)a)->rgb[fvSortChannel] - (int)((const fvBin*)b)->rgb[fvSortChannel];
}

// The channel along which the box is widest, and that width.
static int fvWidestChannel(const fvBin* bins, fvBox box, int* width)
{
	int lo[3] = {31, 31, 31}, hi[3] = {0, 0, 0};
	for (int i = box.first; i < box.last; ++i)
		for (int c = 0; c < 3; ++c)
		{
			lo[c] = bins[i].rgb[c] < lo[c] ? bins[i].rgb[c] : lo[c];
			hi[c] = bins[i].rgb[c] > hi[c] ? bins[i].rgb[c] : hi[c];
		}
	int best = 0;
	for (int c = 1; c < 3; ++c)
		if (hi[c] - lo[c] > hi[best] - lo[best])
			best = c;
	*width = hi[best] - lo[best];
	return best;
}

// Split boxes until there are @p wanted or none can be split: each time the box with the most
// pixels times width, at its median pixel along its widest channel.
static int fvMedianCut(fvBin* bins, int binCount, fvBox* boxes, int wanted)
{
	int count = 1;
	boxes[0] = (fvBox){0, binCount};
	while (count < wanted)
	{
		int pick = -1, channel = 0;
		double bestScore = 0.0;
		for (int b = 0; b < count; ++b)
		{
			int width = 0, c = fvWidestChannel(bins, boxes[b], &width);
			long pixels = 0;
			for (int i = boxes[b].first; i < boxes[b].last; ++i)
				pixels += bins[i].count;
			double score = (double)pixels * width;
			if (boxes[b].last - boxes[b].first > 1 && width > 0 && score > bestScore)
				bestScore = score, pick = b, channel = c;
		}
		if (pick < 0)
			break;
		fvBox box = boxes[pick];
		fvSortChannel = channel;
		qsort(bins + box.first, (size_t)(box.last - box.first), sizeof *bins, fvCompareBins);
		long total = 0, half = 0;
		for (int i = box.first; i < box.last; ++i)
			total += bins[i].count;
		int split = box.first + 1;
		for (int i = box.first; i < box.last - 1 && half + bins[i].count <= total / 2; ++i)
			half += bins[i].count, split = i + 1;
		split = split <= box.first ? box.first + 1 : split;
		boxes[pick].last = split;
		boxes[count++] = (fvBox){split, box.last};
	}
	return count;
}

// The histogram of the coloured (not grey) pixels, as a list of the bins that are used.
static int fvColouredBins(const unsigned char* rgba, size_t pixels, fvBin* bins, long* histogram)
{
	memset(histogram, 0, FV_BINS * sizeof *histogram);
	for (size_t i = 0; i < pixels; ++i)
	{
		const unsigned char* p = rgba + 4 * i;
		int hi = p[0] > p[1] ? p[0] : p[1], lo = p[0] < p[1] ? p[0] : p[1];
		hi = p[2] > hi ? p[2] : hi, lo = p[2] < lo ? p[2] : lo;
		if (hi - lo > FV_SATURATION)
			histogram[((p[0] >> 3) << 10) | ((p[1] >> 3) << 5) | (p[2] >> 3)] += 1;
	}
	int count = 0;
	for (int key = 0; key < FV_BINS; ++key)
		if (histogram[key] > 0)
			bins[count++] = (fvBin){{(unsigned char)(key >> 10), (unsigned char)((key >> 5) & 31),
			                         (unsigned char)(key & 31)},
			                        histogram[key]};
	return count;
}

static void fvAdd(fvPalette* palette, int r, int g, int b)
{
	unsigned char* c = palette->colors[palette->count++];
	c[0] = (unsigned char)r, c[1] = (unsigned char)g, c[2] = (unsigned char)b;
}

// The nearest entry of every 5-bit colour, by a distance weighted as the eye weighs the
// channels (green most, blue least).
static void fvFillNearest(fvPalette* palette)
{
	for (int key = 0; key < FV_BINS; ++key)
	{
		int rgb[3] = {((key >> 10) << 3) + 4, (((key >> 5) & 31) << 3) + 4, ((key & 31) << 3) + 4};
		int best = 0;
		long bestDistance = INT32_MAX;
		for (int i = 0; i < palette->count; ++i)
		{
			long dr = rgb[0] - palette->colors[i][0], dg = rgb[1] - palette->colors[i][1],
			     db = rgb[2] - palette->colors[i][2];
			long distance = 3 * dr * dr + 4 * dg * dg + 2 * db * db;
			if (distance < bestDistance)
				bestDistance = distance, best = i;
		}
		palette->nearest[key] = (unsigned char)best;
	}
}

bool fvPalette_Build(fvPalette* palette, const unsigned char* rgba, size_t pixels)
{
	memset(palette, 0, sizeof *palette);
	for (int k = 0; k < FV_GREY_LEVELS; ++k)
	{
		int v = k * 255 / (FV_GREY_LEVELS - 1);
		fvAdd(palette, v, v, v);
	}
	for (int r = 0; r < FV_CUBE_LEVELS; ++r)
		for (int g = 0; g < FV_CUBE_LEVELS; ++g)
			for (int b = 0; b < FV_CUBE_LEVELS; ++b)
				fvAdd(palette, 85 * r, 85 * g, 85 * b);
	fvBin* bins = malloc(FV_BINS * sizeof *bins);
	long* histogram = malloc(FV_BINS * sizeof *histogram);
	fvBox* boxes = malloc(256 * sizeof *boxes);
	if (bins == NULL || histogram == NULL || boxes == NULL)
	{
		free(bins), free(histogram), free(boxes);
		return false;
	}
	int binCount = fvColouredBins(rgba, pixels, bins, histogram);
	int boxCount = binCount > 0 ? fvMedianCut(bins, binCount, boxes, 255 - palette->count) : 0;
	for (int b = 0; b < boxCount; ++b)
	{
		double sum[3] = {0.0, 0.0, 0.0}, weight = 0.0;
		for (int i = boxes[b].first; i < boxes[b].last; ++i)
			for (int c = 0; c < 3; ++c)
			{
				sum[c] += (double)bins[i].count * (bins[i].rgb[c] * 8 + 4);
				weight += c == 0 ? (double)bins[i].count : 0.0;
			}
		fvAdd(palette, (int)(sum[0] / weight + 0.5), (int)(sum[1] / weight + 0.5),
		      (int)(sum[2] / weight + 0.5));
	}
	free(bins), free(histogram), free(boxes);
	fvFillNearest(palette);
	return true;
}

unsigned char fvPalette_Index(const fvPalette* palette, const unsigned char* rgb)
{
	return palette->nearest[((rgb[0] >> 3) << 10) | ((rgb[1] >> 3) << 5) | (rgb[2] >> 3)];
}
