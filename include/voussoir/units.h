/* Unit conversions at the boundary: the case file and the summaries use mm, N/mm^3 and deg;
 * everything inside is SI. Multiply a value in the named unit by the constant to get SI. */
#ifndef VOUSSOIR_UNITS_H
#define VOUSSOIR_UNITS_H

#define VS_PI 3.14159265358979323846
#define VS_MM 1e-3               /* mm -> m */
#define VS_DEG (VS_PI / 180.0)   /* deg -> rad */
#define VS_N_MM3 1e9             /* N/mm^3 -> N/m^3 */
#define VS_MPA 1e6               /* MPa -> Pa */
#define VS_N_MM 1e3              /* N/mm -> N/m */

#endif
