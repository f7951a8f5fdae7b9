"""Example plug-ins for twinlink, as a third party would write them (docs/plugins.md):

- `tcp_lines`: a connector kind, a TCP listener taking `signal=value` lines;
- `moving_average`: a blueprint, the mean of the last `window` samples of each signal;
- `header_token`: a gateway credential method, a fixed token in a header of your choice.
"""
