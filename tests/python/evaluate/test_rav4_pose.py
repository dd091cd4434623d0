"""The RAV4 drive's pose as the estimator's truth (main_job.pose_truth,
rav4_truth): the conversion of the fused GNSS/IMU pose into the device
frame (the velocity points forward, within the drive's speed range), and
the comparison of an estimate with it (the mount's yaw removed, the RMS
error scored).

Measured on the bundled drive (`make run`): the mount's yaw -0.81 deg; the
estimator's sideslip 0.110 deg RMS from the pose's (beta = 0: 0.101 deg),
its vx 0.257 m/s (1.5 %) above the pose's forward speed."""
import os
import unittest

import numpy as np

from grip_tools.evaluate import main_job
from grip_tools.paths import REPO_ROOT

RAV4 = os.path.join(REPO_ROOT, "tests", "data", "comma2k19-rav4")


@unittest.skipUnless(os.path.isdir(main_job.POSE_DIR), "the RAV4 pose data is not in tests/data")
class PoseTruthTests(unittest.TestCase):
    def test_quaternion_is_a_rotation(self):
        q = np.array([0.21243875, -0.80302968, -0.43522125, -0.34726874])
        q = q / np.linalg.norm(q)
        m = main_job.quat_to_matrix(q)
        np.testing.assert_allclose(m @ m.T, np.eye(3), atol=1e-12)
        self.assertAlmostEqual(float(np.linalg.det(m)), 1.0, places=12)

    def test_device_frame_velocity_points_forward(self):
        t, vd, beta = main_job.pose_truth()
        self.assertEqual(vd.shape, (len(t), 3))
        speed = np.linalg.norm(vd, axis=1)
        self.assertTrue(np.all(vd[:, 0] > 0.95 * speed))     # forward, nearly all of it
        self.assertTrue(np.all(np.abs(vd[:, 1]) < 0.05 * speed + 0.1))
        self.assertGreater(float(np.min(speed)), 7.0)        # 8 -> 20 m/s (README)
        self.assertLess(float(np.max(speed)), 21.0)
        self.assertTrue(np.all(np.abs(np.degrees(beta)) < 3.0))

    def test_comparison_removes_the_mount_and_scores(self):
        t, vd, beta = main_job.pose_truth()
        tt = np.linspace(t[0], t[-1], 3000)
        vx = np.interp(tt, t, vd[:, 0])
        yaw = np.zeros_like(tt)
        perfect = np.interp(tt, t, beta)
        base = dict(t_s=tt, vx=vx, yaw_rate=yaw)
        # the pose's own sideslip less the mount: error 0; a constant offset
        # of 0.5 deg: error 0.5 deg
        m0 = main_job.rav4_truth(dict(base, beta=perfect - np.mean(perfect[vx > 10.0])))
        self.assertLess(m0["beta_rms_deg"], 1e-9)
        m1 = main_job.rav4_truth(dict(base, beta=perfect - np.mean(perfect[vx > 10.0]) + np.radians(0.5)))
        self.assertAlmostEqual(m1["beta_rms_deg"], 0.5, places=6)
        self.assertLess(m1["vx_rms"], 1e-9)
