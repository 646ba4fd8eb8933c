//! Tokens the server reports (`usage` of an OpenAI-compatible chat completion) and what they cost.
//!
//! `usage.prompt_tokens` counts the whole prompt, of which `usage.prompt_tokens_details.cached_tokens`
//! were served from the provider's prompt cache (absent: none counted as cached);
//! `usage.completion_tokens` the answer. Completions from Scenalog's own on-disk cache cost nothing
//! and count no tokens. A server answer without a usable `usage` is counted in
//! [`Usage::without_usage`], so a total that misses some answers says so.

use serde::{Deserialize, Serialize};

/// Token counts, summed over completions.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Usage {
    /// Prompt tokens, cached ones included.
    pub prompt_tokens: u64,
    /// Of the prompt tokens, those the server read from its prompt cache.
    pub cached_tokens: u64,
    /// Completion (output) tokens.
    pub completion_tokens: u64,
    /// Server answers counted.
    pub completions: u64,
    /// Server answers that carried no usable `usage` (not counted in the tokens).
    pub without_usage: u64,
}

impl Usage {
    /// The `usage` of a chat-completions answer; `None` when it is absent or unusable (a count
    /// missing or not a non-negative integer, or more cached tokens than prompt tokens).
    pub fn from_answer(answer: &serde_json::Value) -> Option<Usage> {
        let u = answer.get("usage")?;
        let prompt_tokens = u.get("prompt_tokens")?.as_u64()?;
        let completion_tokens = u.get("completion_tokens")?.as_u64()?;
        let cached_tokens = match u.pointer("/prompt_tokens_details/cached_tokens") {
            None | Some(serde_json::Value::Null) => 0,
            Some(v) => v.as_u64()?,
        };
        (cached_tokens <= prompt_tokens).then_some(Usage {
            prompt_tokens,
            cached_tokens,
            completion_tokens,
            completions: 1,
            without_usage: 0,
        })
    }

    /// One server answer without usable `usage`.
    pub fn missing() -> Usage {
        Usage {
            completions: 1,
            without_usage: 1,
            ..Usage::default()
        }
    }

    /// Prompt tokens not served from the cache.
    pub fn uncached_tokens(&self) -> u64 {
        self.prompt_tokens - self.cached_tokens
    }

    /// The sum of two counts.
    pub fn add(&self, other: &Usage) -> Usage {
        Usage {
            prompt_tokens: self.prompt_tokens + other.prompt_tokens,
            cached_tokens: self.cached_tokens + other.cached_tokens,
            completion_tokens: self.completion_tokens + other.completion_tokens,
            completions: self.completions + other.completions,
            without_usage: self.without_usage + other.without_usage,
        }
    }

    /// The counts as JSON, with the cost at `price` when one is given.
    pub fn to_json(&self, price: Option<&Price>) -> serde_json::Value {
        let mut v = serde_json::json!({
            "prompt_tokens": self.prompt_tokens,
            "cached_tokens": self.cached_tokens,
            "uncached_tokens": self.uncached_tokens(),
            "completion_tokens": self.completion_tokens,
            "completions": self.completions,
            "without_usage": self.without_usage,
        });
        if let Some(p) = price {
            v["cost"] = serde_json::json!(p.cost(self));
        }
        v
    }
}

/// Prices per million tokens: uncached input, cached input, output (`--price IN,CACHED,OUT`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Price {
    /// Per million uncached prompt tokens.
    pub input: f64,
    /// Per million cached prompt tokens.
    pub cached: f64,
    /// Per million completion tokens.
    pub output: f64,
}

impl Price {
    /// Parses `IN,CACHED,OUT`: three finite non-negative numbers.
    pub fn parse(s: &str) -> Result<Price, String> {
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        let bad = || {
            format!(
                "expected IN,CACHED,OUT (prices per million uncached input, cached input and output tokens, e.g. 2,0.5,8), got {s:?}"
            )
        };
        if parts.len() != 3 {
            return Err(bad());
        }
        let mut v = [0.0; 3];
        for (x, p) in v.iter_mut().zip(&parts) {
            *x = p
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite() && *x >= 0.0)
                .ok_or_else(bad)?;
        }
        Ok(Price {
            input: v[0],
            cached: v[1],
            output: v[2],
        })
    }

    /// The cost of `u`: uncached, cached and completion tokens at their prices.
    pub fn cost(&self, u: &Usage) -> f64 {
        (u.uncached_tokens() as f64 * self.input
            + u.cached_tokens as f64 * self.cached
            + u.completion_tokens as f64 * self.output)
            / 1e6
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn usage_with_and_without_cached_details() {
        let with: serde_json::Value = serde_json::from_str(
            r#"{"usage":{"prompt_tokens":1000,"completion_tokens":50,"prompt_tokens_details":{"cached_tokens":768}}}"#,
        )
        .unwrap();
        let u = Usage::from_answer(&with).unwrap();
        assert_eq!(
            (u.prompt_tokens, u.cached_tokens, u.uncached_tokens()),
            (1000, 768, 232)
        );
        let without: serde_json::Value =
            serde_json::from_str(r#"{"usage":{"prompt_tokens":10,"completion_tokens":5}}"#)
                .unwrap();
        assert_eq!(Usage::from_answer(&without).unwrap().cached_tokens, 0);
        for bad in [
            r#"{}"#,
            r#"{"usage":null}"#,
            r#"{"usage":{"prompt_tokens":10}}"#,
            r#"{"usage":{"prompt_tokens":-1,"completion_tokens":5}}"#,
            r#"{"usage":{"prompt_tokens":10,"completion_tokens":5,"prompt_tokens_details":{"cached_tokens":11}}}"#,
        ] {
            let v: serde_json::Value = serde_json::from_str(bad).unwrap();
            assert_eq!(Usage::from_answer(&v), None, "{bad}");
        }
    }

    #[test]
    fn price_and_cost() {
        let p = Price::parse("2, 0.5,8").unwrap();
        let u = Usage {
            prompt_tokens: 1_000_000,
            cached_tokens: 600_000,
            completion_tokens: 100_000,
            completions: 3,
            without_usage: 0,
        };
        // 400k uncached at 2, 600k cached at 0.5, 100k out at 8: 0.8 + 0.3 + 0.8.
        assert!((p.cost(&u) - 1.9).abs() < 1e-12);
        for bad in ["1,2", "1,2,3,4", "a,1,1", "-1,0,0", "inf,0,0", "NaN,0,0"] {
            assert!(Price::parse(bad).is_err(), "{bad}");
        }
    }
}
