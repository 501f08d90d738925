/* Reads lines of 12 numbers (four points, as %a hex floats) and prints
 * poly_orient's sign for each: the test compares with exact rationals. */
#include <stdio.h>

#include "poly_exact.h"

int main(void)
{
  double p[12];
  while (1) {
    for (int k = 0; k < 12; k++)
      if (scanf("%la", &p[k]) != 1) return 0;
    double value = poly_orient(p, p + 3, p + 6, p + 9);
    printf("%d\n", (value > 0) - (value < 0));
  }
}
