"""Trains the fast model on the sample scene (1000 steps: about half a minute on two cores), then shows a
held-out view beside its photo (written to train_sample_scene.png when there is no display). Run
from the repository root with the module on the path (docs/python.md); TRAIN_STEPS sets the steps."""
import os

import matplotlib
import vknerf

if not os.environ.get("DISPLAY"):
    matplotlib.use("Agg")
import matplotlib.pyplot as plt

ctx = vknerf.Context()
trainer = vknerf.Trainer(ctx, vknerf.Dataset.load("assets/tabletop"), vknerf.TrainConfig.fast(ctx, seed=0))
trainer.train(steps=int(os.environ.get("TRAIN_STEPS", 1000)))
test = vknerf.Dataset.load("assets/tabletop", split="test")
model = trainer.model()
scores = vknerf.evaluate(model, test)
print(f"held-out PSNR {scores['mean_psnr']:.2f} dB, SSIM {scores['mean_ssim']:.4f} over {len(test)} views")

fig, (photo, render) = plt.subplots(1, 2, figsize=(8, 4))
photo.imshow(test.image(0)), photo.set_title("photo"), photo.axis("off")
render.imshow(model.render(test.cameras[0])["rgb"].clip(0, 1)), render.axis("off")
render.set_title(f"render ({scores['psnr'][0]:.2f} dB)")
plt.show() if os.environ.get("DISPLAY") else fig.savefig("train_sample_scene.png", bbox_inches="tight")
