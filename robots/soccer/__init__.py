"""One-on-one robot soccer at Khepera scale: the field, the ball on its pitch, and the referee."""
