//! Which deterministic slice of a run this process traces (`--shard I/N|auto|auto/N`). `auto`
//! reads the slice from a job array's environment: Slurm (`SLURM_ARRAY_TASK_ID` −
//! `SLURM_ARRAY_TASK_MIN` of `SLURM_ARRAY_TASK_COUNT`), AWS Batch (`AWS_BATCH_JOB_ARRAY_INDEX` of
//! `AWS_BATCH_JOB_ARRAY_SIZE`), or Kubernetes Indexed Jobs (`JOB_COMPLETION_INDEX`, with N given
//! as `auto/N`, since the pod is not told the job's completions). The environment comes in as a
//! function, so that callers pass `std::env::var` and tests a table.
//!
//! ```
//! let env = |k: &str| (k == "JOB_COMPLETION_INDEX").then(|| "2".to_string());
//! assert_eq!(mc::job_array::slice("auto/3", &env).unwrap(), (3, 3));
//! assert_eq!(mc::job_array::slice("2/4", &|_| None).unwrap(), (2, 4));
//! ```

use crate::error::{McError, Result};

/// A refusal of the slice or its environment.
fn refuse(message: String) -> McError {
    McError::Slice(message)
}

fn number(var: &str, v: &str) -> Result<u64> {
    v.trim()
        .parse()
        .map_err(|_| refuse(format!("invalid {var} = {v:?}: not a non-negative integer")))
}

/// The slice (1-based I, N) a `--shard` value `s` names, reading `env` (a variable's value, if
/// set) for `auto`.
pub fn slice(s: &str, env: &dyn Fn(&str) -> Option<String>) -> Result<(u64, u64)> {
    let bad = || {
        refuse(format!(
            "invalid --shard {s:?}: expected I/N with 1 ≤ I ≤ N, auto, or auto/N"
        ))
    };
    let (head, tail) = match s.split_once('/') {
        Some((h, t)) => (h.trim(), Some(t.trim())),
        None => (s.trim(), None),
    };
    let given_n = tail
        .map(|t| t.parse::<u64>().map_err(|_| bad()))
        .transpose()?;
    let (i, n) = if head == "auto" {
        auto(env, given_n)?
    } else {
        let i: u64 = head.parse().map_err(|_| bad())?;
        (i, given_n.ok_or_else(bad)?)
    };
    if i == 0 || i > n {
        return Err(refuse(format!(
            "invalid --shard {s:?}: slice {i} of {n} is not within 1..={n}"
        )));
    }
    Ok((i, n))
}

fn auto(env: &dyn Fn(&str) -> Option<String>, given_n: Option<u64>) -> Result<(u64, u64)> {
    let get = |k: &str| env(k).map(|v| number(k, &v)).transpose();
    let agree = |n: u64, var: &str| match given_n {
        Some(g) if g != n => Err(refuse(format!(
            "invalid --shard auto/{g}: {var} says the array has {n} tasks"
        ))),
        _ => Ok(n),
    };
    if let Some(id) = get("SLURM_ARRAY_TASK_ID")? {
        if let Some(step) = get("SLURM_ARRAY_TASK_STEP")?
            && step != 1
        {
            return Err(refuse(format!(
                "--shard auto: SLURM_ARRAY_TASK_STEP = {step}; submit the array without a step (--array=0-N)"
            )));
        }
        let min = get("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let count = get("SLURM_ARRAY_TASK_COUNT")?.ok_or_else(|| {
            refuse(
                "--shard auto: SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not".into(),
            )
        })?;
        let i = id.checked_sub(min).ok_or_else(|| {
            refuse(format!(
                "--shard auto: SLURM_ARRAY_TASK_ID = {id} is below SLURM_ARRAY_TASK_MIN = {min}"
            ))
        })?;
        return Ok((i + 1, agree(count, "SLURM_ARRAY_TASK_COUNT")?));
    }
    if let Some(i) = get("AWS_BATCH_JOB_ARRAY_INDEX")? {
        let n = get("AWS_BATCH_JOB_ARRAY_SIZE")?.ok_or_else(|| {
            refuse(
                "--shard auto: AWS_BATCH_JOB_ARRAY_INDEX is set but AWS_BATCH_JOB_ARRAY_SIZE is not"
                    .into(),
            )
        })?;
        return Ok((i + 1, agree(n, "AWS_BATCH_JOB_ARRAY_SIZE")?));
    }
    if let Some(i) = get("JOB_COMPLETION_INDEX")? {
        let n = given_n.ok_or_else(|| {
            refuse(format!("--shard auto: JOB_COMPLETION_INDEX = {i} is set (a Kubernetes Indexed Job); give the number of completions as --shard auto/N"))
        })?;
        return Ok((i + 1, n));
    }
    Err(refuse(
        "--shard auto: no job array in the environment (none of SLURM_ARRAY_TASK_ID, \
         AWS_BATCH_JOB_ARRAY_INDEX, JOB_COMPLETION_INDEX is set); give --shard I/N"
            .into(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with(vars: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let v: Vec<(String, String)> = vars
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect();
        move |k| v.iter().find(|(a, _)| a == k).map(|(_, b)| b.clone())
    }

    #[test]
    fn explicit_slices_and_job_arrays() {
        let none = with(&[]);
        assert_eq!(slice("2/4", &none).unwrap(), (2, 4));
        assert!(slice("0/4", &none).is_err());
        assert!(slice("5/4", &none).is_err());
        assert!(slice("2", &none).is_err());
        let e = slice("auto", &none).unwrap_err().to_string();
        assert!(e.contains("SLURM_ARRAY_TASK_ID"), "{e}");
        let slurm = with(&[
            ("SLURM_ARRAY_TASK_ID", "7"),
            ("SLURM_ARRAY_TASK_MIN", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ]);
        assert_eq!(slice("auto", &slurm).unwrap(), (4, 4));
        assert!(slice("auto/3", &slurm).is_err());
        let stepped = with(&[
            ("SLURM_ARRAY_TASK_ID", "2"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
        ]);
        assert!(slice("auto", &stepped).is_err());
        let aws = with(&[
            ("AWS_BATCH_JOB_ARRAY_INDEX", "0"),
            ("AWS_BATCH_JOB_ARRAY_SIZE", "3"),
        ]);
        assert_eq!(slice("auto", &aws).unwrap(), (1, 3));
        let k8s = with(&[("JOB_COMPLETION_INDEX", "2")]);
        assert_eq!(slice("auto/3", &k8s).unwrap(), (3, 3));
        assert!(slice("auto", &k8s).is_err());
        assert!(slice("auto/2", &k8s).is_err());
    }
}
