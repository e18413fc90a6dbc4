//! Adam (Kingma & Ba), with bias correction, on a flat parameter vector.

/// Adam optimizer state: learning rate, moment decays and the running first/second moments.
#[derive(Debug, Clone)]
pub struct Adam {
    lr: f64,
    beta1: f64,
    beta2: f64,
    eps: f64,
    t: i32,
    m: Vec<f64>,
    v: Vec<f64>,
}

impl Adam {
    /// Fresh state for `len` parameters: learning rate `lr`, moment decays `beta1` and `beta2`,
    /// ε = 1e-8.
    pub fn new(len: usize, lr: f64, beta1: f64, beta2: f64) -> Self {
        Adam {
            lr,
            beta1,
            beta2,
            eps: 1e-8,
            t: 0,
            m: vec![0.0; len],
            v: vec![0.0; len],
        }
    }

    /// One descent step of `params` along `grad`.
    pub fn step(&mut self, params: &mut [f64], grad: &[f64]) {
        self.t += 1;
        let c1 = 1.0 - self.beta1.powi(self.t);
        let c2 = 1.0 - self.beta2.powi(self.t);
        for ((p, g), (m, v)) in params
            .iter_mut()
            .zip(grad)
            .zip(self.m.iter_mut().zip(self.v.iter_mut()))
        {
            *m = self.beta1 * *m + (1.0 - self.beta1) * g;
            *v = self.beta2 * *v + (1.0 - self.beta2) * g * g;
            *p -= self.lr * (*m / c1) / ((*v / c2).sqrt() + self.eps);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adam_minimises_a_quadratic() {
        let mut x = vec![5.0, -3.0];
        let mut adam = Adam::new(2, 0.1, 0.9, 0.999);
        for _ in 0..2000 {
            let g: Vec<f64> = x.iter().map(|v| 2.0 * (v - 1.0)).collect();
            adam.step(&mut x, &g);
        }
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-3), "{x:?}");
    }
}
