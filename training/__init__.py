"""Online self-organised training of EKMs (thesis ch. 4.3) as jitted ``lax.scan`` loops."""
