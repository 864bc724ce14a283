"""Example Python nodes (type "py.image_math.NAME"), shipped in Loom's
share/loom/python, the last folder of the Python node path."""

import numpy as np

import loom


@loom.node(inputs={"image": loom.In("Image", doc="the image"),
                   "gamma": loom.In("Float", 2.2, "the exponent: out = in^(1/gamma)", range=(0.05, 20))},
           outputs={"image": loom.Out("Image", "the corrected image, same encoding")})
def Gamma(image, gamma):
    """Gamma correction of the color channels (alpha kept): out = in^(1/gamma), negative values kept at 0."""
    out = np.array(image, dtype=np.float32)
    color = out[:, :, :3] if out.shape[2] >= 3 else out[:, :, :1]
    color[...] = np.power(np.maximum(color, 0), 1.0 / gamma)
    return loom.Image(out, image.encoding, image.space)


@loom.node(inputs={"image": loom.In("Image", doc="the image")},
           outputs={"mean": loom.Out("FloatList", "the mean of each channel"),
                    "histogram": loom.Out("Json", "counts of 16 equal bins over [0, 1] per channel")})
def ChannelStats(image):
    """Per-channel mean and a 16-bin histogram over [0, 1]."""
    a = np.asarray(image)
    hist = [np.histogram(a[:, :, c], bins=16, range=(0, 1))[0].tolist() for c in range(a.shape[2])]
    return {"mean": a.reshape(-1, a.shape[2]).mean(axis=0).astype(float).tolist(), "histogram": {"bins": hist}}
